// gearnvh.atlas, orbits, tiers and validate on a gear train (schema gearnvh/2): the app functions
// behind `gearnvh atlas|orbits|tiers|validate TRAIN.yaml` (one plan function per command checks
// the options for both), per-mesh and per-loose-gear results as objects and NumPy arrays, and
// to_dict() giving the command line's JSON.
#include <fmt/format.h>
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <limits>
#include <memory>
#include <optional>

#include "binding_support.h"
#include "gearbox.h"
#include "simulate_command.h"
#include "train_atlas_command.h"
#include "train_call.h"
#include "train_orbits_command.h"
#include "train_tiers.h"
#include "train_validation.h"
#include "validate_command.h"
#include "validation_ladder.h"

namespace gearnvh::python {

namespace {

struct TrainAtlas {
  app::TrainAtlasResult result;
  nlohmann::json doc;  // the `atlas --json` document
};

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

struct Validation {
  std::vector<app::ValidationRow> rows;
  nlohmann::json doc;  // the `validate --json` document
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::shared_ptr<TrainAtlas> AtlasTrain(const Train& train, const std::optional<std::string>& x,
                                       const std::optional<std::string>& y, const py::object& tier,
                                       std::optional<long> cycles, std::optional<long> transient,
                                       int jobs, const std::string& method,
                                       const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto options = TrainCommandOptions<app::AtlasCommandOptions>(source, tier, method);
        options.x = x;
        options.y = y;
        options.cycles = cycles;
        options.transient = transient;
        options.jobs = jobs;
        return app::PlanTrainAtlas(options, spec, kKeywordNames);
      },
      [&](app::TrainAtlasPlan& plan, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        plan.atlas.cancel = &control.cancel;
        auto out = std::make_shared<TrainAtlas>();
        out->result = app::RunTrainAtlas(spec, plan.x, plan.y, plan.atlas, plan.jobs,
                                         [&](int d, int t) { control.Progress(d, t); });
        out->doc = app::TrainAtlasDocument(out->result, plan.atlas, spec, source);
        return out;
      },
      progress);
}

std::shared_ptr<TrainOrbits> OrbitsTrain(const Train& train, int period,
                                         const std::optional<std::string>& sweep,
                                         const py::object& tier, std::optional<long> transient,
                                         const std::string& method, const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto options = TrainCommandOptions<app::OrbitsCommandOptions>(source, tier, method);
        options.period = period;
        options.sweep = sweep;
        options.transient = transient;
        return app::PlanTrainOrbits(options, spec, kKeywordNames);
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
                                       std::optional<long> transient, const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        app::TiersCommandOptions options;
        options.file = source;
        options.cycles = cycles;
        options.transient = transient;
        return app::PlanTrainTiers(options, spec, kKeywordNames);
      },
      [&](app::TrainRunOptions& run, const TrainSpec& spec, const std::string& source,
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

std::shared_ptr<Validation> ValidateTrain(const Train& train, const py::object& progress) {
  const TrainSpec spec = train.spec();
  const std::string source = train.source();
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] {
          auto out = std::make_shared<Validation>();
          out->rows = app::RunTrainValidationLadder(spec, &control.cancel,
                                                    [&](int d, int t) { control.Progress(d, t); });
          out->doc = app::ValidationDocument(out->rows, spec.name, source);
          return out;
        });
      },
      progress);
}

// The pair's ladder (`gearnvh validate FILE` on a schema-1 file). It has no progress counts and
// no cancellation point: Ctrl-C stops it when it ends (about a second on the examples).
std::shared_ptr<Validation> ValidateGearbox(const Gearbox& gearbox, const py::object& progress) {
  const GearboxSpec spec = gearbox.spec();
  const std::string source = gearbox.source();
  return RunInterruptible(
      [&](CallControl&) {
        return NamingSource(source, [&] {
          auto out = std::make_shared<Validation>();
          out->rows = app::RunValidationLadder(spec);
          out->doc = app::ValidationDocument(out->rows, spec.name, source);
          return out;
        });
      },
      progress);
}

// (rows, columns) of value(cell) over the atlas grid; NaN for a failed cell.
template <typename Value>
py::array_t<double> AtlasGrid(const app::TrainAtlasResult& r, Value&& value) {
  const long nx = r.x.range.points, ny = r.y.range.points;
  py::array_t<double> out({ny, nx});
  auto m = out.mutable_unchecked<2>();
  for (const app::TrainAtlasCell& c : r.cells) m(c.iy, c.ix) = c.point.ok ? value(c.point) : kNaN;
  return out;
}

// (items, rows, columns): one grid per mesh or loose gear.
template <typename Value>
py::array_t<double> AtlasGrids(const app::TrainAtlasResult& r, size_t items, Value&& value) {
  const long nx = r.x.range.points, ny = r.y.range.points;
  py::array_t<double> out({static_cast<long>(items), ny, nx});
  auto m = out.mutable_unchecked<3>();
  for (const app::TrainAtlasCell& c : r.cells) {
    for (size_t i = 0; i < items; ++i) {
      m(static_cast<py::ssize_t>(i), c.iy, c.ix) = c.point.ok ? value(c.point, i) : kNaN;
    }
  }
  return out;
}

// (meshes, rows, columns) of a mesh's field.
py::cpp_function MeshGrids(double TrainAtlasMesh::*member) {
  return py::cpp_function([member](const TrainAtlas& a) {
    return AtlasGrids(a.result, a.result.mesh_names.size(),
                      [member](const TrainAtlasPoint& p, size_t i) { return p.meshes[i].*member; });
  });
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

// A regime name per cell (row-major nested lists), "failed" for a failed cell.
template <typename Regime>
std::vector<std::vector<std::string>> RegimeGrid(const app::TrainAtlasResult& r, Regime&& regime) {
  std::vector<std::vector<std::string>> grid(static_cast<size_t>(r.y.range.points));
  for (const app::TrainAtlasCell& c : r.cells) {
    grid[static_cast<size_t>(c.iy)].push_back(c.point.ok ? RattleRegimeName(regime(c.point))
                                                         : "failed");
  }
  return grid;
}

}  // namespace

void BindTrainAnalyses(py::module_& m) {
  // Atlas.
  py::class_<TrainAtlasMesh>(m, "TrainAtlasMesh", "One mesh in one atlas cell.")
      .def_readonly("name", &TrainAtlasMesh::name)
      .def_readonly("drive_impacts_per_cycle", &TrainAtlasMesh::drive_impacts_per_cycle,
                    "per cycle of this mesh")
      .def_readonly("back_impacts_per_cycle", &TrainAtlasMesh::back_impacts_per_cycle)
      .def_readonly("separation_fraction", &TrainAtlasMesh::separation_fraction)
      .def_readonly("impact_velocity_rms", &TrainAtlasMesh::impact_velocity_rms, "m/s")
      .def_property_readonly("regime",
                             [](const TrainAtlasMesh& g) { return RattleRegimeName(g.regime); })
      .def("__repr__", [](const TrainAtlasMesh& g) {
        return fmt::format("<gearnvh.TrainAtlasMesh {} {}>", g.name, RattleRegimeName(g.regime));
      });
  py::class_<TrainAtlasLooseGear>(m, "TrainAtlasLooseGear", "One loose gear in one atlas cell.")
      .def_readonly("name", &TrainAtlasLooseGear::name)
      .def_readonly("rattle_index", &TrainAtlasLooseGear::rattle_index,
                    "RMS angular acceleration about the mean, rad/s^2")
      .def_readonly("impacts", &TrainAtlasLooseGear::impacts)
      .def_readonly("rank", &TrainAtlasLooseGear::rank, "1 = rattles most in this cell")
      .def("__repr__", [](const TrainAtlasLooseGear& g) {
        return fmt::format("<gearnvh.TrainAtlasLooseGear {}. {}, {:.4g} rad/s^2>", g.rank, g.name,
                           g.rattle_index);
      });
  py::class_<TrainAtlasPoint>(m, "TrainAtlasCell", "One cell of a train's atlas.")
      .def_readonly("ok", &TrainAtlasPoint::ok)
      .def_readonly("message", &TrainAtlasPoint::message, "why the cell failed")
      .def_readonly("lyapunov_per_s", &TrainAtlasPoint::lyapunov_per_s)
      .def_readonly("lyapunov_per_forcing_cycle", &TrainAtlasPoint::lyapunov_per_forcing_cycle)
      .def_readonly("lyapunov_standard_error", &TrainAtlasPoint::lyapunov_standard_error, "1/s")
      .def_property_readonly(
          "regime",
          [](const TrainAtlasPoint& p) { return p.ok ? RattleRegimeName(p.regime) : "failed"; })
      .def_readonly("meshes", &TrainAtlasPoint::meshes, "TrainAtlasMesh per mesh, file order")
      .def_readonly("loose_gears", &TrainAtlasPoint::loose_gears,
                    "TrainAtlasLooseGear by rank (1 = rattles most)")
      .def_readonly("wall_s", &TrainAtlasPoint::wall_s)
      .def("__repr__", [](const TrainAtlasPoint& p) {
        if (!p.ok) return "<gearnvh.TrainAtlasCell failed: " + p.message + ">";
        return fmt::format("<gearnvh.TrainAtlasCell {}, lambda {:.4g} per forcing cycle>",
                           RattleRegimeName(p.regime), p.lyapunov_per_forcing_cycle);
      });

  py::class_<TrainAtlas, std::shared_ptr<TrainAtlas>>(
      m, "TrainAtlas",
      "A gear train's chaos atlas (gearnvh atlas TRAIN.yaml). Grids have shape (len(y), len(x)); "
      "per-mesh and per-loose-gear grids (items, len(y), len(x)); NaN in a failed cell.")
      .def_property_readonly("x_parameter",
                             [](const TrainAtlas& a) { return a.result.x.parameter; })
      .def_property_readonly("y_parameter",
                             [](const TrainAtlas& a) { return a.result.y.parameter; })
      .def_property_readonly(
          "x", [](const TrainAtlas& a) { return AxisValues(a.result.x); }, "SI")
      .def_property_readonly(
          "y", [](const TrainAtlas& a) { return AxisValues(a.result.y); }, "SI")
      .def_property_readonly("mesh_names", [](const TrainAtlas& a) { return a.result.mesh_names; })
      .def_property_readonly("loose_gear_names",
                             [](const TrainAtlas& a) { return a.result.loose_gear_names; })
      .def(
          "cell",
          [](py::object self, int ix, int iy) {
            const app::TrainAtlasResult& r = self.cast<const TrainAtlas&>().result;
            if (ix < 0 || ix >= r.x.range.points || iy < 0 || iy >= r.y.range.points) {
              throw py::index_error("atlas cell (" + std::to_string(ix) + ", " +
                                    std::to_string(iy) + ") outside the grid");
            }
            const TrainAtlasPoint& p =
                r.cells[static_cast<size_t>(iy * r.x.range.points + ix)].point;
            return py::cast(p, py::return_value_policy::reference_internal, self);
          },
          py::arg("ix"), py::arg("iy"), "The TrainAtlasCell at column ix (x), row iy (y).")
      .def_property_readonly(
          "lyapunov_per_s",
          [](const TrainAtlas& a) {
            return AtlasGrid(a.result, [](const TrainAtlasPoint& p) { return p.lyapunov_per_s; });
          },
          "the train's largest Lyapunov exponent, 1/s")
      .def_property_readonly("lyapunov_per_forcing_cycle",
                             [](const TrainAtlas& a) {
                               return AtlasGrid(a.result, [](const TrainAtlasPoint& p) {
                                 return p.lyapunov_per_forcing_cycle;
                               });
                             })
      .def_property_readonly("lyapunov_standard_error",
                             [](const TrainAtlas& a) {
                               return AtlasGrid(a.result, [](const TrainAtlasPoint& p) {
                                 return p.lyapunov_standard_error;
                               });
                             })
      .def_property_readonly(
          "regime",
          [](const TrainAtlas& a) {
            return RegimeGrid(a.result, [](const TrainAtlasPoint& p) { return p.regime; });
          },
          "the train's regime per cell (nested lists)")
      .def_property_readonly(
          "mesh_regime",
          [](const TrainAtlas& a) {
            std::vector<std::vector<std::vector<std::string>>> out;
            for (size_t i = 0; i < a.result.mesh_names.size(); ++i) {
              out.push_back(RegimeGrid(
                  a.result, [i](const TrainAtlasPoint& p) { return p.meshes[i].regime; }));
            }
            return out;
          },
          "per mesh, its regime per cell")
      .def_property_readonly("drive_impacts_per_cycle",
                             MeshGrids(&TrainAtlasMesh::drive_impacts_per_cycle))
      .def_property_readonly("back_impacts_per_cycle",
                             MeshGrids(&TrainAtlasMesh::back_impacts_per_cycle))
      .def_property_readonly("separation_fraction", MeshGrids(&TrainAtlasMesh::separation_fraction))
      .def_property_readonly("impact_velocity_rms", MeshGrids(&TrainAtlasMesh::impact_velocity_rms))
      .def_property_readonly(
          "rattle_index",
          [](const TrainAtlas& a) {
            const std::vector<std::string>& names = a.result.loose_gear_names;
            return AtlasGrids(a.result, names.size(), [&](const TrainAtlasPoint& p, size_t g) {
              for (const TrainAtlasLooseGear& lg : p.loose_gears) {
                if (lg.name == names[g]) return lg.rattle_index;
              }
              return kNaN;
            });
          },
          "(loose gears, len(y), len(x)), rad/s^2, in the order of loose_gear_names")
      .def_property_readonly("failed", [](const TrainAtlas& a) { return a.result.Failed(); })
      .def(
          "to_dict", [](const TrainAtlas& a) { return ToPython(a.doc); },
          "The document `gearnvh atlas --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainAtlas& a) {
        return fmt::format("<gearnvh.TrainAtlas {} x {}: {} x {} cells, {} failed>",
                           a.result.x.parameter, a.result.y.parameter, a.result.x.range.points,
                           a.result.y.range.points, a.result.Failed());
      });

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
          "Floquet multipliers on the quotient by the free rotation (2n - 2), by decreasing "
          "modulus")
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
        if (!p.point.found())
          return fmt::format("<gearnvh.TrainOrbitPoint {:.6g}: not found>", p.value);
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
          "finest", [](const TrainTiers& t) { return t.comparison.rows[t.comparison.finest].name; },
          "the tier with the most DOF, the reference of the differences")
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

  // Validation.
  py::class_<app::ValidationRow>(m, "ValidationCheck", "One row of the validation ladder.")
      .def_readonly("name", &app::ValidationRow::name)
      .def_readonly("value", &app::ValidationRow::value)
      .def_readonly("threshold", &app::ValidationRow::threshold)
      .def_readonly("passed", &app::ValidationRow::pass, "value <= threshold")
      .def_readonly("skipped", &app::ValidationRow::skipped)
      .def_readonly("detail", &app::ValidationRow::detail, "what was compared, or why skipped")
      .def("__repr__", [](const app::ValidationRow& r) {
        return "<gearnvh.ValidationCheck " + r.name + ": " +
               (r.skipped ? "skipped" : (r.pass ? "pass" : "FAIL")) + ">";
      });
  py::class_<Validation, std::shared_ptr<Validation>>(
      m, "Validation", "The validation ladder of a gearbox (gearnvh validate).")
      .def_readonly("checks", &Validation::rows)
      .def_property_readonly("passed",
                             [](const Validation& v) { return v.doc["pass"].get<bool>(); })
      .def(
          "to_dict", [](const Validation& v) { return ToPython(v.doc); },
          "The document `gearnvh validate --json` prints.")
      .def("__repr__", [](const Validation& v) {
        long passed = 0, skipped = 0;
        for (const app::ValidationRow& r : v.rows) {
          skipped += r.skipped ? 1 : 0;
          passed += !r.skipped && r.pass ? 1 : 0;
        }
        return fmt::format("<gearnvh.Validation {}: {} of {} checks passed, {} skipped>",
                           v.doc["pass"].get<bool>() ? "pass" : "FAIL", passed,
                           v.rows.size() - static_cast<size_t>(skipped), skipped);
      });

  m.def("atlas", &AtlasTrain, py::arg("gearbox"), py::kw_only(), py::arg("x") = py::none(),
        py::arg("y") = py::none(), py::arg("tier") = py::none(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("jobs") = 0, py::arg("method") = "v3",
        py::arg("progress") = py::none(),
        "A gear train's chaos atlas, as `gearnvh atlas TRAIN.yaml`: x, y like "
        "'operating.loads[1].torque=0Nm:2Nm:8' (default analysis.atlas); cycles and transient "
        "count cycles of the first mesh (defaults 1080 and 300).");
  m.def("orbits", &OrbitsTrain, py::arg("gearbox"), py::kw_only(), py::arg("period") = 1,
        py::arg("sweep") = py::none(), py::arg("tier") = py::none(),
        py::arg("transient") = py::none(), py::arg("method") = "v3",
        py::arg("progress") = py::none(),
        "A gear train's period-M orbits (M common periods) and Floquet multipliers, as `gearnvh "
        "orbits TRAIN.yaml`; sweep like 'meshes[0].backlash=50um:150um:5'.");
  m.def("tiers", &TiersTrain, py::arg("gearbox"), py::kw_only(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("progress") = py::none(),
        "Every tier of a gear train side by side, as `gearnvh tiers TRAIN.yaml` (cycles default "
        "min(analysis.cycles, 400), transient min(analysis.transient_cycles, 200)).");
  m.def("validate", &ValidateTrain, py::arg("gearbox"), py::kw_only(),
        py::arg("progress") = py::none(),
        "The validation ladder of a gear train, as `gearnvh validate TRAIN.yaml`: the exact "
        "solver against the CVODE reference and its V2 and V1 event methods.");
  m.def("validate", &ValidateGearbox, py::arg("gearbox"), py::kw_only(),
        py::arg("progress") = py::none(),
        "The validation ladder of a gear pair, as `gearnvh validate FILE`: fused vs stepped "
        "propagation, exact vs CVODE reference, closed forms, segment convergence, MTA "
        "compliance, ISO 6336 stiffness. No progress counts; Ctrl-C stops it when it ends.");
}

}  // namespace gearnvh::python
