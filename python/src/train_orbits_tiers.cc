// gearnvh.orbits and gearnvh.tiers on a gear train (schema gearnvh/2): the app functions behind
// `gearnvh orbits|tiers TRAIN.yaml` (one plan function per command checks the options for both),
// per-point and per-tier results as objects and NumPy arrays, and to_dict() giving the command
// line's JSON.
#include <fmt/format.h>
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <memory>
#include <optional>

#include "binding_support.h"
#include "gearbox.h"
#include "train_call.h"
#include "train_orbits_command.h"
#include "train_tiers.h"

namespace gearnvh::python {

namespace {

struct TrainOrbitsPoint {
  double value = 0.0;  // the swept parameter, SI (0 without a sweep)
  TrainOrbitScanPoint point;
};

struct TrainOrbits {
  std::string parameter;
  std::vector<TrainOrbitsPoint> points;
  nlohmann::json doc;  // the `orbits --json` document
};

struct TrainTiers {
  app::TrainTiersComparison comparison;
  nlohmann::json doc;  // the `tiers --json` document
};

std::shared_ptr<TrainOrbits> OrbitsTrain(const Train& train, int period,
                                         const std::optional<std::string>& sweep,
                                         const py::object& tier, std::optional<long> transient,
                                         const std::string& method, bool allow_slow,
                                         const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto options = TrainCommandOptions<app::OrbitsCommandOptions>(source, tier, method);
        options.period = period;
        options.sweep = sweep;
        options.transient = transient;
        options.allow_slow = allow_slow;
        app::TrainOrbitsPlan plan = app::PlanTrainOrbits(options, spec, kKeywordNames);
        (void)app::CheckTrainOrbitsCost(spec, plan);  // refuses; its warning is not kept
        return plan;
      },
      [&](app::TrainOrbitsPlan& plan, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        plan.scan.cancel = &control.cancel;
        const std::vector<TrainOrbitScanPoint> points =
            app::RunTrainOrbits(spec, plan, [&](int d, int t) { control.Progress(d, t); });
        auto out = std::make_shared<TrainOrbits>();
        out->doc = app::TrainOrbitsDocument(points, plan, spec, source);
        out->parameter = out->doc["parameter"].get<std::string>();
        for (size_t i = 0; i < points.size(); ++i)
          out->points.push_back({plan.values[i], points[i]});
        return out;
      },
      progress);
}

std::shared_ptr<TrainTiers> TiersTrain(const Train& train, std::optional<long> cycles,
                                       std::optional<long> transient, bool allow_slow,
                                       const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        app::TiersCommandOptions options;
        options.file = source;
        options.cycles = cycles;
        options.transient = transient;
        options.allow_slow = allow_slow;
        return app::PlanTrainTiers(options, spec, kKeywordNames);
      },
      [&](gearnvh::TrainRunOptions& run, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        run.cancel = &control.cancel;
        auto out = std::make_shared<TrainTiers>();
        out->comparison =
            app::CompareTrainTiers(spec, run, [&](size_t d, size_t t, const std::string&) {
              control.Progress(static_cast<long>(d) - 1, static_cast<long>(t));
            });
        control.Progress(static_cast<long>(out->comparison.rows.size()),
                         static_cast<long>(out->comparison.rows.size()));
        out->doc = app::TrainTiersDocument(out->comparison, spec, source);
        return out;
      },
      progress);
}

// A per-tier array of a row's scalar (a view) and a (tiers, items) array of a row's list.
template <typename Field>
py::cpp_function TrainTierField(Field app::TrainTierRow::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const TrainTiers&>().comparison.rows, member, self);
  });
}

py::cpp_function TrainTierRows(std::vector<double> app::TrainTierRow::*member) {
  return py::cpp_function([member](const TrainTiers& t) {
    std::vector<std::vector<double>> rows;
    for (const app::TrainTierRow& r : t.comparison.rows) rows.push_back(r.*member);
    return Matrix(rows);
  });
}

}  // namespace

void BindTrainOrbitsTiers(py::module_& m) {
  // Orbits.
  py::class_<TrainOrbitsPoint>(m, "TrainOrbitPoint",
                               "A period-M orbit of a train at one parameter value.")
      .def_readonly("value", &TrainOrbitsPoint::value, "parameter value, SI (0 without a sweep)")
      .def_property_readonly("ok", [](const TrainOrbitsPoint& p) { return p.point.ok; })
      .def_property_readonly("found", [](const TrainOrbitsPoint& p) { return p.point.found(); })
      .def_property_readonly(
          "stable",
          [](const TrainOrbitsPoint& p) { return p.point.found() && p.point.orbit.stable; })
      .def_property_readonly(
          "start", [](const TrainOrbitsPoint& p) { return TrainOrbitStartText(p.point); },
          "which start converged: 'continuation', 'settled run + k periods' or ''")
      .def_property_readonly("message", [](const TrainOrbitsPoint& p) { return p.point.message; })
      .def_property_readonly(
          "info", [](const TrainOrbitsPoint& p) { return TrainOrbitInfoName(p.point.orbit.info); })
      .def_property_readonly("iterations",
                             [](const TrainOrbitsPoint& p) { return p.point.orbit.iterations; })
      .def_property_readonly("residual",
                             [](const TrainOrbitsPoint& p) { return p.point.orbit.residual; })
      .def_property_readonly(
          "multipliers",
          [](const TrainOrbitsPoint& p) {
            const Eigen::VectorXcd& mu = p.point.orbit.multipliers;
            return py::array_t<std::complex<double>>(mu.size(), mu.data());
          },
          "Floquet multipliers on the quotient by the neutral directions (2n - 2: the free "
          "rotation's angle and speed; 2n - 1 when a viscous drag damps its speed; 2 fewer per "
          "fixed shaft), by decreasing modulus")
      .def_property_readonly("spectral_radius",
                             [](const TrainOrbitsPoint& p) {
                               const Eigen::VectorXcd& mu = p.point.orbit.multipliers;
                               return mu.size() > 0 ? std::abs(mu[0]) : 0.0;
                             })
      .def_property_readonly(
          "period_s", [](const TrainOrbitsPoint& p) { return p.point.orbit.period; },
          "the orbit's period, s (M common periods)")
      .def_property_readonly("common_period_s",
                             [](const TrainOrbitsPoint& p) { return p.point.common_period; })
      .def_property_readonly(
          "events_per_period",
          [](const TrainOrbitsPoint& p) { return p.point.orbit.events_per_period; })
      .def("__repr__", [](const TrainOrbitsPoint& p) {
        if (!p.point.ok) {
          return fmt::format("<gearnvh.TrainOrbitPoint {:.6g}: failed: {}>", p.value,
                             p.point.message);
        }
        if (!p.point.found()) {
          return fmt::format("<gearnvh.TrainOrbitPoint {:.6g}: not found>", p.value);
        }
        const Eigen::VectorXcd& mu = p.point.orbit.multipliers;
        return fmt::format("<gearnvh.TrainOrbitPoint {:.6g}: {}, max |mu| {:.4g}>", p.value,
                           p.point.orbit.stable ? "stable" : "unstable",
                           mu.size() > 0 ? std::abs(mu[0]) : 0.0);
      });

  py::class_<TrainOrbits, std::shared_ptr<TrainOrbits>>(
      m, "TrainOrbits", "Periodic orbits of a gear train (gearnvh orbits TRAIN.yaml).")
      .def_readonly("parameter", &TrainOrbits::parameter)
      .def_property_readonly(
          "points",
          [](py::object self) {
            py::list out;
            for (const TrainOrbitsPoint& p : self.cast<const TrainOrbits&>().points) {
              out.append(py::cast(p, py::return_value_policy::reference_internal, self));
            }
            return out;
          })
      .def(
          "to_dict", [](const TrainOrbits& o) { return ToPython(o.doc); },
          "The document `gearnvh orbits --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainOrbits& o) {
        long found = 0;
        for (const TrainOrbitsPoint& p : o.points) found += p.point.found() ? 1 : 0;
        return fmt::format("<gearnvh.TrainOrbits {} points{}, {} found>", o.points.size(),
                           o.parameter.empty() ? std::string() : " along " + o.parameter, found);
      });

  // Tiers.
  py::class_<TrainTiers, std::shared_ptr<TrainTiers>>(
      m, "TrainTiers",
      "Every tier of a train side by side (gearnvh tiers TRAIN.yaml); per-tier arrays, "
      "(tiers, meshes) and (tiers, loose gears) arrays.")
      .def_property_readonly("names",
                             [](const TrainTiers& t) {
                               std::vector<std::string> v;
                               for (const app::TrainTierRow& r : t.comparison.rows)
                                 v.push_back(r.name);
                               return v;
                             })
      .def_property_readonly("mesh_names", [](const TrainTiers& t) { return t.comparison.meshes; })
      .def_property_readonly("loose_gear_names",
                             [](const TrainTiers& t) { return t.comparison.loose_gears; })
      .def_property_readonly(
          "ok",
          [](const TrainTiers& t) {
            return PerRow(t.comparison.rows, [](const app::TrainTierRow& r) { return r.ok(); });
          },
          "per tier: the run finished (a failed tier's results are NaN)")
      .def_property_readonly(
          "statuses",
          [](const TrainTiers& t) {
            return PerRow(t.comparison.rows, [](const app::TrainTierRow& r) {
              return std::string(TrainStepperInfoName(r.info));
            });
          },
          "per tier: 'success', 'too many events' or 'out of range'")
      .def_property_readonly(
          "messages",
          [](const TrainTiers& t) {
            return PerRow(t.comparison.rows, [](const app::TrainTierRow& r) { return r.message; });
          },
          "per tier: why the run stopped ('' when it did not)")
      .def_property_readonly("failed", [](const TrainTiers& t) { return t.comparison.failed; })
      .def_property_readonly(
          "finest",
          [](const TrainTiers& t) -> std::optional<std::string> {
            const app::TrainTierRow& finest = t.comparison.rows[t.comparison.finest];
            return finest.ok() ? std::optional(finest.name) : std::nullopt;
          },
          "the tier with the most DOF whose run finished (None when none did), the reference of "
          "the differences")
      .def_property_readonly("dof", TrainTierField(&app::TrainTierRow::dof))
      .def_property_readonly("state_dim", TrainTierField(&app::TrainTierRow::state_dim))
      .def_property_readonly("us_per_cycle", TrainTierField(&app::TrainTierRow::us_per_cycle),
                             "µs per cycle of the first mesh")
      .def_property_readonly("real_time_ratio", TrainTierField(&app::TrainTierRow::real_time_ratio))
      .def_property_readonly("table_bytes", TrainTierField(&app::TrainTierRow::table_bytes),
                             "peak table cache bytes")
      .def_property_readonly("te_rms", TrainTierRows(&app::TrainTierRow::te_rms),
                             "m, (tiers, meshes)")
      .def_property_readonly("te_rms_difference",
                             TrainTierRows(&app::TrainTierRow::te_rms_difference),
                             "relative to the finest tier")
      .def_property_readonly("rattle_index", TrainTierRows(&app::TrainTierRow::rattle_index),
                             "rad/s^2, (tiers, loose gears)")
      .def_property_readonly("rattle_index_difference",
                             TrainTierRows(&app::TrainTierRow::rattle_index_difference))
      .def(
          "to_dict", [](const TrainTiers& t) { return ToPython(t.doc); },
          "The document `gearnvh tiers --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainTiers& t) {
        std::string names;
        for (const app::TrainTierRow& r : t.comparison.rows) {
          names += (names.empty() ? "" : ", ") + r.name;
        }
        return "<gearnvh.TrainTiers " + names + ">";
      });

  m.def("orbits", &OrbitsTrain, py::arg("gearbox"), py::kw_only(), py::arg("period") = 1,
        py::arg("sweep") = py::none(), py::arg("tier") = py::none(),
        py::arg("transient") = py::none(), py::arg("method") = "v3", py::arg("allow_slow") = false,
        py::arg("progress") = py::none(),
        "A gear train's period-M orbits (M common periods) and Floquet multipliers, as `gearnvh "
        "orbits TRAIN.yaml`; sweep like 'meshes[0].backlash=50um:150um:5'.");
  m.def("tiers", &TiersTrain, py::arg("gearbox"), py::kw_only(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("allow_slow") = false,
        py::arg("progress") = py::none(),
        "Every tier of a gear train side by side, as `gearnvh tiers TRAIN.yaml` (cycles default "
        "min(analysis.cycles, 400), transient min(analysis.transient_cycles, 200)).");
}

}  // namespace gearnvh::python
