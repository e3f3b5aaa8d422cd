// gearnvh.sweep / atlas / orbits / tiers: the library calls behind the commands of those names,
// with grids and series as NumPy arrays (views where the C++ layout allows).
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "atlas_command.h"
#include "binding_support.h"
#include "config/gearbox_loader.h"
#include "gearbox.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/orbit_scan.h"
#include "gearnvh/reduction/reduced_model.h"
#include "speed_sweep.h"
#include "sweep_command.h"
#include "tiers_command.h"

namespace gearnvh::python {

namespace {

struct Sweep {
  app::SpeedSweepResult result;
  nlohmann::json doc;  // the `sweep --json` document
};

struct Atlas {
  AtlasResult result;
  nlohmann::json doc;  // the `atlas --json` document
};

struct Orbits {
  std::vector<OrbitScanPoint> points;
  std::string parameter;
};

struct Tiers {
  app::TiersComparison comparison;
  nlohmann::json doc;  // the `tiers --json` document
};

std::shared_ptr<Sweep> RunSweep(const Gearbox& gb, const py::object& tier,
                                std::optional<long> cycles, std::optional<long> transient, int jobs,
                                const std::string& method, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  const Tier chosen = TierArgument(tier, spec.analysis.tier);
  app::SpeedSweepOptions options;
  options.cycles = cycles.value_or(options.cycles);
  options.transient_cycles = transient.value_or(options.transient_cycles);
  options.waterfall_cycles = std::min(options.waterfall_cycles, options.cycles - 1);
  options.threads = jobs;
  options.method = method;
  {
    SolverOptions probe;
    ApplyMethodName(method, probe, "method");
  }
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] {
          options.cancel = &control.cancel;
          const ComponentModel model = BuildComponentModel(spec);
          const ReducedModel reduced = ReduceModel(model, chosen);
          auto out = std::make_shared<Sweep>();
          out->result = app::RunSpeedSweep(spec, model, reduced, options,
                                           [&](int d, int t) { control.Progress(d, t); });
          out->doc = app::SweepJson(out->result, spec.pinion.teeth);
          out->doc["name"] = spec.name;
          out->doc["file"] = source;
          out->doc["tier"] = reduced.name;
          out->doc["cycles_per_speed"] = options.cycles;
          out->doc["transient_cycles"] = options.transient_cycles;
          int failed = 0;
          for (const app::SpeedPoint& p : out->result.points) failed += p.ok ? 0 : 1;
          out->doc["failed_speeds"] = failed;
          return out;
        });
      },
      progress);
}

std::shared_ptr<Atlas> RunAtlas(const Gearbox& gb, const std::optional<std::string>& x,
                                const std::optional<std::string>& y, const py::object& tier,
                                std::optional<long> cycles, std::optional<long> transient, int jobs,
                                const std::string& method, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  AtlasOptions options;
  options.tier = TierArgument(tier, spec.analysis.tier);
  options.cycles = cycles.value_or(options.cycles);
  options.transient_cycles = transient.value_or(options.transient_cycles);
  options.threads = jobs;
  options.method = method == "fused" ? "v3" : method;
  std::optional<AtlasAxis> ax = spec.analysis.atlas_x, ay = spec.analysis.atlas_y;
  if (x) ax = config::ParseAxisOption(*x, "x");
  if (y) ay = config::ParseAxisOption(*y, "y");
  if (!ax || !ay) {
    throw InputError("analysis.atlas", 0, "(missing)",
                     "an atlas needs two axes: analysis.atlas.x and .y in the gearbox, or x= and "
                     "y= ('operating.speed=600rpm:3000rpm:24')",
                     source);
  }
  if (ax->parameter == ay->parameter) {
    throw InputError("y", 0, ay->parameter, "must differ from the x parameter", source);
  }
  NamingSource(source, [&] { options.Validate(); });
  return RunInterruptible(
      [&](CallControl& control) {
        options.cancel = &control.cancel;
        auto out = std::make_shared<Atlas>();
        out->result =
            RunChaosAtlas(spec, *ax, *ay, options, [&](int d, int t) { control.Progress(d, t); });
        options.cancel = nullptr;
        out->doc = app::AtlasJson(out->result, options);
        out->doc["name"] = spec.name;
        out->doc["file"] = source;
        return out;
      },
      progress);
}

std::shared_ptr<Orbits> RunOrbits(const Gearbox& gb, int period,
                                  const std::optional<std::string>& sweep, const py::object& tier,
                                  std::optional<long> transient, const std::string& method,
                                  const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  OrbitScanOptions options;
  options.tier = TierArgument(tier, spec.analysis.tier);
  options.period = period;
  options.transient_cycles = transient.value_or(spec.analysis.transient_cycles);
  options.method = method == "fused" ? "v3" : method;
  std::optional<AtlasAxis> axis;
  if (sweep) axis = config::ParseAxisOption(*sweep, "sweep");
  NamingSource(source, [&] { options.Validate(); });
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
  ApplyMethodName("v3", solver);
  solver.cycles = cycles.value_or(std::min(spec.analysis.cycles, 400));
  solver.transient_cycles = transient.value_or(std::min(spec.analysis.transient_cycles, 200));
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
py::cpp_function SpeedField(Field app::SpeedPoint::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Sweep&>().result.points, member, self);
  });
}

template <typename Field>
py::cpp_function CellGrid(Field AtlasCell::*member) {
  return py::cpp_function([member](py::object self) {
    const AtlasResult& r = self.cast<const Atlas&>().result;
    return GridView(r.cells, member, r.y.range.points, r.x.range.points, self);
  });
}

py::array_t<double> AxisValues(const AtlasAxis& a) {
  py::array_t<double> v(a.range.points);
  for (int i = 0; i < a.range.points; ++i) v.mutable_at(i) = AxisValue(a, i);
  return v;
}

template <typename Field>
py::cpp_function TierField(Field app::TierRow::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Tiers&>().comparison.rows, member, self);
  });
}

}  // namespace

void BindAnalyses(py::module_& m) {
  py::class_<Sweep, std::shared_ptr<Sweep>>(
      m, "Sweep",
      "Speed sweep (gearnvh sweep): Campbell data and a waterfall, one exact run per speed. "
      "Per-speed attributes are read-only NumPy views.")
      .def_property_readonly("speeds_rpm", SpeedField(&app::SpeedPoint::speed_rpm))
      .def_property_readonly("speeds_rad_s", SpeedField(&app::SpeedPoint::speed_rad_s))
      .def_property_readonly("te_rms", SpeedField(&app::SpeedPoint::te_rms), "m per speed")
      .def_property_readonly("te_peak_to_peak", SpeedField(&app::SpeedPoint::te_peak_to_peak))
      .def_property_readonly("events_per_cycle", SpeedField(&app::SpeedPoint::events_per_cycle))
      .def_property_readonly("ok",
                             [](const Sweep& s) {
                               std::vector<bool> ok;
                               for (const auto& p : s.result.points) ok.push_back(p.ok);
                               return ok;
                             })
      .def_property_readonly("regimes",
                             [](const Sweep& s) {
                               std::vector<std::string> r;
                               for (const auto& p : s.result.points) r.push_back(p.regime);
                               return r;
                             })
      .def_property_readonly(
          "order_step", [](const Sweep& s) { return s.result.order_step; },
          "pinion orders per waterfall bin")
      .def_property_readonly(
          "orders",
          [](const Sweep& s) {
            py::array_t<double> o(s.result.order_bins);
            for (int k = 0; k < s.result.order_bins; ++k) o.mutable_at(k) = k * s.result.order_step;
            return o;
          },
          "pinion order of each waterfall bin")
      .def_property_readonly(
          "waterfall",
          [](const Sweep& s) {
            std::vector<std::vector<double>> rows;
            for (const auto& p : s.result.points) rows.push_back(p.amplitude_m);
            return Matrix(rows);
          },
          "TE amplitude, m: (speeds, order bins)")
      .def_property_readonly(
          "campbell_hz", [](const Sweep& s) { return Matrix(s.result.campbell.frequency_hz); },
          "natural frequency of each tracked mode, Hz: (modes, speeds); NaN where not found")
      .def_property_readonly(
          "campbell_damping",
          [](const Sweep& s) { return Matrix(s.result.campbell.damping_ratio); }, "(modes, speeds)")
      .def_property_readonly("campbell_mac",
                             [](const Sweep& s) { return Matrix(s.result.campbell.mac); })
      .def_property_readonly("mode_labels",
                             [](const Sweep& s) {
                               std::vector<std::string> labels;
                               for (const ModeInfo& i : s.result.campbell.modes)
                                 labels.push_back(i.Label());
                               return labels;
                             })
      .def_property_readonly(
          "critical_speeds",
          [](const Sweep& s) { return ToPython(s.doc["campbell"]["critical_speeds"]); },
          "list of {order, mode, mode_label, speed_rpm, frequency_hz}")
      .def(
          "to_dict", [](const Sweep& s) { return ToPython(s.doc); },
          "The document `gearnvh sweep --json` prints.");

  py::class_<Atlas, std::shared_ptr<Atlas>>(
      m, "Atlas",
      "Chaos atlas (gearnvh atlas). Grids have shape (len(y), len(x)) and are read-only NumPy "
      "views of the cells.")
      .def_property_readonly("x_parameter", [](const Atlas& a) { return a.result.x.parameter; })
      .def_property_readonly("y_parameter", [](const Atlas& a) { return a.result.y.parameter; })
      .def_property_readonly(
          "x", [](const Atlas& a) { return AxisValues(a.result.x); }, "SI")
      .def_property_readonly(
          "y", [](const Atlas& a) { return AxisValues(a.result.y); }, "SI")
      .def_property_readonly("lyapunov_per_s", CellGrid(&AtlasCell::lyapunov_per_s))
      .def_property_readonly("lyapunov_per_forcing_cycle",
                             CellGrid(&AtlasCell::lyapunov_per_forcing_cycle))
      .def_property_readonly("lyapunov_standard_error",
                             CellGrid(&AtlasCell::lyapunov_standard_error))
      .def_property_readonly("drive_impacts_per_cycle",
                             CellGrid(&AtlasCell::drive_impacts_per_cycle))
      .def_property_readonly("back_impacts_per_cycle", CellGrid(&AtlasCell::back_impacts_per_cycle))
      .def_property_readonly("rattle_index", CellGrid(&AtlasCell::rattle_index),
                             "impact energy per forcing cycle, J")
      .def_property_readonly("impact_velocity_rms", CellGrid(&AtlasCell::impact_velocity_rms))
      .def_property_readonly("separation_fraction", CellGrid(&AtlasCell::separation_fraction))
      .def_property_readonly(
          "regime",
          [](const Atlas& a) {
            std::vector<std::vector<std::string>> grid(
                static_cast<size_t>(a.result.y.range.points));
            for (const AtlasCell& c : a.result.cells) {
              grid[static_cast<size_t>(c.iy)].push_back(c.ok ? c.regime : "failed");
            }
            return grid;
          })
      .def_property_readonly("failed", [](const Atlas& a) { return a.result.Failed(); })
      .def(
          "to_dict", [](const Atlas& a) { return ToPython(a.doc); },
          "The document `gearnvh atlas --json` prints.");

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
                             [](const OrbitScanPoint& p) { return p.orbit.back_impacts; });

  py::class_<Orbits, std::shared_ptr<Orbits>>(m, "Orbits", "Periodic orbits (gearnvh orbits).")
      .def_readonly("parameter", &Orbits::parameter)
      .def_property_readonly("points", [](py::object self) {
        py::list out;
        for (const OrbitScanPoint& p : self.cast<const Orbits&>().points) {
          out.append(py::cast(p, py::return_value_policy::reference_internal, self));
        }
        return out;
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
          "finest", [](const Tiers& t) { return t.comparison.rows[t.comparison.finest].name; })
      .def(
          "to_dict", [](const Tiers& t) { return ToPython(t.doc); },
          "The document `gearnvh tiers --json` prints.");

  m.def("sweep", &RunSweep, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("cycles") = py::none(), py::arg("transient") = py::none(), py::arg("jobs") = 0,
        py::arg("method") = "fused", py::arg("progress") = py::none(),
        "Speed sweep over analysis.speed_sweep, as `gearnvh sweep` (cycles default 512, "
        "transient 200, jobs 0 = all cores).");
  m.def("atlas", &RunAtlas, py::arg("gearbox"), py::kw_only(), py::arg("x") = py::none(),
        py::arg("y") = py::none(), py::arg("tier") = py::none(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("jobs") = 0, py::arg("method") = "v3",
        py::arg("progress") = py::none(),
        "Chaos atlas over two parameters, as `gearnvh atlas`: x, y like "
        "'operating.speed=600rpm:3000rpm:24' (default analysis.atlas).");
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
