// gearnvh.atlas on a gear train (schema gearnvh/2): the app functions behind `gearnvh atlas
// TRAIN.yaml` (PlanTrainAtlas checks the options for both), per-cell, per-mesh and per-loose-gear
// grids as NumPy arrays, and to_dict() giving the command line's JSON.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>
#include <optional>

#include "binding_support.h"
#include "gearbox.h"
#include "train_atlas_command.h"
#include "train_call.h"

namespace gearnvh::python {

namespace {

struct TrainAtlas {
  gearnvh::TrainAtlasResult result;
  nlohmann::json doc;  // the `atlas --json` document
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::shared_ptr<TrainAtlas> AtlasTrain(const Train& train, const std::optional<std::string>& x,
                                       const std::optional<std::string>& y, const py::object& tier,
                                       std::optional<long> cycles, std::optional<long> transient,
                                       int jobs, const std::string& method, bool allow_slow,
                                       const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto options =
            TrainCommandOptions<app::AtlasCommandOptions>(source, tier, method, cycles, transient);
        options.x = x;
        options.y = y;
        options.jobs = jobs;
        options.allow_slow = allow_slow;
        app::TrainAtlasPlan plan = app::PlanTrainAtlas(options, spec, kKeywordNames);
        (void)app::CheckTrainAtlasCost(spec, plan);  // refuses; its warning is not kept
        return plan;
      },
      [&](app::TrainAtlasPlan& plan, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        plan.atlas.cancel = &control.cancel;
        auto out = std::make_shared<TrainAtlas>();
        out->result = gearnvh::RunTrainAtlas(spec, plan.x, plan.y, plan.atlas, plan.jobs,
                                             [&](int d, int t) { control.Progress(d, t); });
        out->doc = app::TrainAtlasDocument(out->result, plan.atlas, spec, source);
        return out;
      },
      progress);
}

// (rows, columns) of value(cell) over the atlas grid; NaN for a failed cell.
template <typename Value>
py::array_t<double> AtlasGrid(const gearnvh::TrainAtlasResult& r, Value&& value) {
  const long nx = r.x.range.points, ny = r.y.range.points;
  py::array_t<double> out({ny, nx});
  auto m = out.mutable_unchecked<2>();
  for (const gearnvh::TrainAtlasCell& c : r.cells)
    m(c.iy, c.ix) = c.point.ok ? value(c.point) : kNaN;
  return out;
}

// (items, rows, columns): one grid per mesh or loose gear.
template <typename Value>
py::array_t<double> AtlasGrids(const gearnvh::TrainAtlasResult& r, size_t items, Value&& value) {
  const long nx = r.x.range.points, ny = r.y.range.points;
  py::array_t<double> out({static_cast<long>(items), ny, nx});
  auto m = out.mutable_unchecked<3>();
  for (const gearnvh::TrainAtlasCell& c : r.cells) {
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

// (loose gears, rows, columns) of a loose gear's field, in the order of loose_gear_names (a cell
// lists its gears by rank); NaN where a gear is missing.
py::cpp_function LooseGearGrids(double TrainAtlasLooseGear::*member) {
  return py::cpp_function([member](const TrainAtlas& a) {
    const std::vector<std::string>& names = a.result.loose_gear_names;
    return AtlasGrids(a.result, names.size(), [&names, member](const TrainAtlasPoint& p, size_t g) {
      for (const TrainAtlasLooseGear& lg : p.loose_gears) {
        if (lg.name == names[g]) return lg.*member;
      }
      return kNaN;
    });
  });
}

// A regime name per cell (row-major nested lists), "failed" for a failed cell.
template <typename Regime>
std::vector<std::vector<std::string>> RegimeGrid(const gearnvh::TrainAtlasResult& r,
                                                 Regime&& regime) {
  std::vector<std::vector<std::string>> grid(static_cast<size_t>(r.y.range.points));
  for (const gearnvh::TrainAtlasCell& c : r.cells) {
    grid[static_cast<size_t>(c.iy)].push_back(c.point.ok ? RattleRegimeName(regime(c.point))
                                                         : "failed");
  }
  return grid;
}

}  // namespace

void BindTrainAtlas(py::module_& m) {
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
      .def_readonly("rank", &TrainAtlasLooseGear::rank,
                    "1 = largest impact energy per second in this cell; 0 = no impact")
      .def_readonly("impact_energy_per_second", &TrainAtlasLooseGear::impact_energy_per_second, "W")
      .def("__repr__", [](const TrainAtlasLooseGear& g) {
        return fmt::format("<gearnvh.TrainAtlasLooseGear {} {}, {:.4g} W>",
                           g.rank > 0 ? std::to_string(g.rank) + "." : "-", g.name,
                           g.impact_energy_per_second);
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
                    "TrainAtlasLooseGear by rank (1 = the largest impact energy), then the gears "
                    "without impacts (rank 0)")
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
            const gearnvh::TrainAtlasResult& r = self.cast<const TrainAtlas&>().result;
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
      .def_property_readonly("rattle_index", LooseGearGrids(&TrainAtlasLooseGear::rattle_index),
                             "(loose gears, len(y), len(x)), rad/s^2, in the order of "
                             "loose_gear_names")
      .def_property_readonly("impact_energy_per_second",
                             LooseGearGrids(&TrainAtlasLooseGear::impact_energy_per_second),
                             "(loose gears, len(y), len(x)), W, in the order of loose_gear_names")
      .def_property_readonly("failed", [](const TrainAtlas& a) { return a.result.Failed(); })
      .def(
          "to_dict", [](const TrainAtlas& a) { return ToPython(a.doc); },
          "The document `gearnvh atlas --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainAtlas& a) {
        return fmt::format("<gearnvh.TrainAtlas {} x {}: {} x {} cells, {} failed>",
                           a.result.x.parameter, a.result.y.parameter, a.result.x.range.points,
                           a.result.y.range.points, a.result.Failed());
      });

  m.def("atlas", &AtlasTrain, py::arg("gearbox"), py::kw_only(), py::arg("x") = py::none(),
        py::arg("y") = py::none(), py::arg("tier") = py::none(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("jobs") = 0, py::arg("method") = "v3",
        py::arg("allow_slow") = false, py::arg("progress") = py::none(),
        "A gear train's chaos atlas, as `gearnvh atlas TRAIN.yaml`: x, y like "
        "'operating.loads[1].torque=0Nm:2Nm:8' (default analysis.atlas); cycles and transient "
        "count cycles of the first mesh (defaults 1080 and 300).");
}

}  // namespace gearnvh::python
