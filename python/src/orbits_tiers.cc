// gearnvh.orbits and gearnvh.tiers: the library calls behind `gearnvh orbits` and `gearnvh tiers`.
#include <fmt/format.h>
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "atlas_command.h"
#include "binding_support.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "gearbox.h"
#include "gearnvh/nvh/orbit_scan.h"
#include "orbits_command.h"
#include "simulate_command.h"
#include "tiers_command.h"
#include "train_command_options.h"

namespace gearnvh::python {

namespace {

struct Orbits {
  std::vector<OrbitScanPoint> points;
  std::string parameter;
};

struct Tiers {
  app::TiersComparison comparison;
  nlohmann::json doc;  // the `tiers --json` document
};

std::shared_ptr<Orbits> RunOrbits(const Gearbox& gb, int period,
                                  const std::optional<std::string>& sweep, const py::object& tier,
                                  std::optional<long> transient, const std::string& method,
                                  const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  OrbitScanOptions options;
  options.input_error_message = app::UserWording(kKeywordInputNames, app::PairAxisValueText(spec));
  options.tier = TierArgument(tier, spec.analysis.tier, source);
  options.period = period;
  options.transient_cycles = transient.value_or(spec.analysis.transient_cycles);
  options.events =
      EventMethodOf(NamingSource(source, [&] { return app::ParseMethod(method, "method"); }));
  std::optional<AtlasAxis> axis;
  if (sweep) {
    axis = config::ParseAxisOption(*sweep, "sweep");
    NamingSource(source, [&] { app::RequirePairAxisOption(spec, *axis, *sweep, "sweep"); });
  }
  NamingSource(source, [&] {
    app::RequireOrbitPeriod(period, "period");
    // The transient, then at least one cycle per base period of the period searched.
    RequirePairRunLength(spec, app::LowestInputSpeed(TrainOf(spec), axis), period,
                         options.transient_cycles, std::nullopt, transient, false);
    options.Validate();
  });
  return RunInterruptible(
      [&](CallControl& control) {
        options.cancel = &control.cancel;
        auto out = std::make_shared<Orbits>();
        out->points =
            ScanPeriodicOrbits(spec, axis, options, [&](int d, int t) { control.Progress(d, t); });
        out->parameter = axis ? axis->parameter : "operating point";
        return out;
      },
      progress);
}

std::shared_ptr<Tiers> RunTiers(const Gearbox& gb, std::optional<long> cycles,
                                std::optional<long> transient, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  SolverOptions solver;
  ApplyLadderMethod(LadderMethod::kV3, solver);
  solver.cycles = cycles.value_or(std::min(spec.analysis.cycles, 400));
  solver.transient_cycles = transient.value_or(std::min(spec.analysis.transient_cycles, 200));
  NamingSource(source, [&] {
    RequirePairRunLength(spec, spec.operating.speed, solver.cycles, solver.transient_cycles, cycles,
                         transient, false);
  });
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] {
          solver.cancel = &control.cancel;
          auto out = std::make_shared<Tiers>();
          out->comparison =
              app::CompareTiers(spec, solver, [&](size_t d, size_t t, const std::string&) {
                control.Progress(static_cast<long>(d), static_cast<long>(t));
              });
          out->doc = out->comparison.doc;
          out->doc["name"] = spec.name;
          out->doc["file"] = source;
          return out;
        });
      },
      progress);
}

template <typename Field>
py::cpp_function TierField(Field app::TierRow::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Tiers&>().comparison.rows, member, self);
  });
}

}  // namespace

void BindOrbitsTiers(py::module_& m) {
  py::class_<OrbitScanPoint>(m, "OrbitPoint", "A periodic orbit at one parameter value.")
      .def_readonly("value", &OrbitScanPoint::value, "parameter value, SI")
      .def_readonly("ok", &OrbitScanPoint::ok)
      .def_readonly("message", &OrbitScanPoint::message)
      .def_readonly("start", &OrbitScanPoint::start, "which start converged; '' when none")
      .def_property_readonly("found", [](const OrbitScanPoint& p) { return !p.start.empty(); })
      .def_property_readonly(
          "stable", [](const OrbitScanPoint& p) { return !p.start.empty() && p.orbit.stable; })
      .def_property_readonly("spectral_radius",
                             [](const OrbitScanPoint& p) { return p.orbit.spectral_radius; })
      .def_property_readonly(
          "multipliers", [](const OrbitScanPoint& p) { return p.orbit.multipliers; },
          "Floquet multipliers, by decreasing modulus")
      .def_property_readonly(
          "nearest_boundary",
          [](const OrbitScanPoint& p) { return StabilityBoundaryName(p.orbit.nearest_boundary); })
      .def_property_readonly("boundary_distance",
                             [](const OrbitScanPoint& p) { return p.orbit.boundary_distance; })
      .def_property_readonly("period_s", [](const OrbitScanPoint& p) { return p.orbit.period_s; })
      .def_property_readonly("drive_impacts_per_period",
                             [](const OrbitScanPoint& p) { return p.orbit.drive_impacts; })
      .def_property_readonly("back_impacts_per_period",
                             [](const OrbitScanPoint& p) { return p.orbit.back_impacts; })
      .def("__repr__", [](const OrbitScanPoint& p) {
        if (!p.ok)
          return fmt::format("<gearnvh.OrbitPoint {:.6g}: failed: {}>", p.value, p.message);
        if (p.start.empty()) return fmt::format("<gearnvh.OrbitPoint {:.6g}: not found>", p.value);
        return fmt::format("<gearnvh.OrbitPoint {:.6g}: {}, max |mu| {:.4g}>", p.value,
                           p.orbit.stable ? "stable" : "unstable", p.orbit.spectral_radius);
      });

  py::class_<Orbits, std::shared_ptr<Orbits>>(m, "Orbits", "Periodic orbits (gearnvh orbits).")
      .def_readonly("parameter", &Orbits::parameter)
      .def_property_readonly(
          "points",
          [](py::object self) {
            py::list out;
            for (const OrbitScanPoint& p : self.cast<const Orbits&>().points) {
              out.append(py::cast(p, py::return_value_policy::reference_internal, self));
            }
            return out;
          })
      .def("__repr__", [](const Orbits& o) {
        long found = 0;
        for (const OrbitScanPoint& p : o.points) found += p.start.empty() ? 0 : 1;
        return fmt::format("<gearnvh.Orbits {} points{}, {} found>", o.points.size(),
                           o.parameter.empty() ? std::string() : " along " + o.parameter, found);
      });

  py::class_<Tiers, std::shared_ptr<Tiers>>(
      m, "Tiers", "Modal truncation levels side by side (gearnvh tiers); one entry per tier.")
      .def_property_readonly("names",
                             [](const Tiers& t) {
                               std::vector<std::string> names;
                               for (const app::TierRow& r : t.comparison.rows)
                                 names.push_back(r.name);
                               return names;
                             })
      .def_property_readonly("te_rms", TierField(&app::TierRow::te_rms), "m")
      .def_property_readonly("rattle_index", TierField(&app::TierRow::rattle_index), "J")
      .def_property_readonly("max_frequency_error", TierField(&app::TierRow::max_frequency_error))
      .def_property_readonly("us_per_cycle", TierField(&app::TierRow::us_per_cycle))
      .def_property_readonly("real_time_ratio", TierField(&app::TierRow::real_time_ratio))
      .def_property_readonly(
          "ok",
          [](const Tiers& t) {
            return PerRow(t.comparison.rows, [](const app::TierRow& r) { return r.ok(); });
          },
          "per tier: the run finished (a failed tier's results are NaN)")
      .def_property_readonly(
          "statuses",
          [](const Tiers& t) {
            return PerRow(t.comparison.rows, [](const app::TierRow& r) {
              return std::string(SolverStatusName(r.status));
            });
          },
          "per tier: 'success', 'too_many_events' or 'out_of_range'")
      .def_property_readonly(
          "messages",
          [](const Tiers& t) {
            return PerRow(t.comparison.rows, [](const app::TierRow& r) { return r.message; });
          },
          "per tier: why the run stopped ('' when it did not)")
      .def_property_readonly("failed", [](const Tiers& t) { return t.comparison.failed; })
      .def_property_readonly(
          "finest",
          [](const Tiers& t) -> std::optional<std::string> {
            const app::TierRow& finest = t.comparison.rows[t.comparison.finest];
            return finest.ok() ? std::optional(finest.name) : std::nullopt;
          },
          "the tier with the most DOF whose run finished (None when none did)")
      .def(
          "to_dict", [](const Tiers& t) { return ToPython(t.doc); },
          "The document `gearnvh tiers --json` prints.")
      .def("__repr__", [](const Tiers& t) {
        std::string names;
        for (const app::TierRow& r : t.comparison.rows)
          names += (names.empty() ? "" : ", ") + r.name;
        return "<gearnvh.Tiers " + names + ">";
      });

  m.def("orbits", &RunOrbits, py::arg("gearbox"), py::kw_only(), py::arg("period") = 1,
        py::arg("sweep") = py::none(), py::arg("tier") = py::none(),
        py::arg("transient") = py::none(), py::arg("method") = "v3",
        py::arg("progress") = py::none(),
        "Periodic orbits, Floquet multipliers and stability, as `gearnvh orbits`; sweep like "
        "'operating.torque=0.1Nm:1Nm:10'.");
  m.def("tiers", &RunTiers, py::arg("gearbox"), py::kw_only(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("progress") = py::none(),
        "Modal tiers side by side, as `gearnvh tiers`.");
}

}  // namespace gearnvh::python
