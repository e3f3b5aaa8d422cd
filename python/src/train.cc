// gearnvh.Train (schema gearnvh/2) and check, simulate (with its Lyapunov exponents) and sweep on
// it: the library calls behind `gearnvh check|simulate|sweep TRAIN.yaml`, per-mesh and
// per-loose-gear results as objects and NumPy arrays (speeds x meshes), and to_dict() giving the
// command line's JSON.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "binding_support.h"
#include "gearbox.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/count_text.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "simulate_command.h"
#include "simulate_train.h"
#include "train_call.h"
#include "train_check.h"
#include "train_sweep_command.h"

namespace gearnvh::python {

namespace {

struct TrainSimulation {
  gearnvh::TrainOperatingPoint op;
  std::optional<TrainLyapunovSummary> lyapunov;  // lyapunov=K
  nlohmann::json doc;                            // the `simulate --json` document
};

struct TrainSweep {
  gearnvh::TrainSweepResult result;
  nlohmann::json doc;  // the `sweep --json` document
};

py::object CheckTrain(const Train& train) {
  const nlohmann::json doc = RunOnModel(
      train,
      [](const TrainSpec& spec, const std::string& source, CallControl& control) {
        nlohmann::json out =
            app::TrainCheckReport(spec, app::BuildTrainCheck(spec, &control.cancel));
        out["file"] = source;
        return out;
      },
      py::none());
  return ToPython(doc);
}

std::shared_ptr<TrainSimulation> SimulateTrain(const Train& train, const py::object& tier,
                                               std::optional<long> cycles,
                                               std::optional<long> transient,
                                               const std::string& method,
                                               std::optional<int> lyapunov, bool histories,
                                               bool allow_slow, const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto options =
            TrainCommandOptions<app::SimulateOptions>(source, tier, method, cycles, transient);
        options.lyapunov = lyapunov;
        options.allow_slow = allow_slow;
        app::TrainSimulatePlan plan = app::PlanTrainSimulate(options, spec, kKeywordNames);
        plan.run.histories = histories;
        // The command line's memory check (docs/cli.md, "Memory"), at the keyword or the file's
        // analysis.cycles.
        plan.run.before_run_memory = [at = cycles ? kKeywordNames("cycles")
                                                  : std::string("analysis.cycles"),
                                      value = std::to_string(plan.run.cycles)](RunMemory& need) {
          return CheckRunMemory(need, AvailableMemory(), at, value);
        };
        return plan;
      },
      [&](app::TrainSimulatePlan& plan, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        plan.run.cancel = &control.cancel;
        // Progress in thousandths of each run: the operating point, then the Lyapunov run.
        constexpr long kSteps = 1000;
        const long total = plan.lyapunov ? 2 * kSteps : kSteps;
        auto out = std::make_shared<TrainSimulation>();
        out->op = gearnvh::RunTrainOperatingPoint(spec, plan.run, [&](double time, double end) {
          control.Progress(std::lround(kSteps * time / end), total);
        });
        out->doc = app::TrainSimulationJson(out->op, spec, source, plan.run.tier);
        if (plan.lyapunov && out->op.ok()) {
          out->lyapunov =
              app::RunTrainLyapunov(out->op, plan.run, *plan.lyapunov, [&](double fraction) {
                control.Progress(kSteps + std::lround(kSteps * fraction), total);
              });
          out->doc["lyapunov"] = app::TrainLyapunovJson(*out->lyapunov);
        }
        return out;
      },
      progress);
}

std::shared_ptr<TrainSweep> SweepTrain(const Train& train, const py::object& tier,
                                       std::optional<long> cycles, std::optional<long> transient,
                                       int jobs, const std::string& method, bool allow_slow,
                                       const py::object& progress) {
  return PlanAndRunOnTrain(
      train,
      [&](const TrainSpec& spec, const std::string& source) {
        auto sweep =
            TrainCommandOptions<app::SweepOptions>(source, tier, method, cycles, transient);
        sweep.jobs = jobs;
        sweep.allow_slow = allow_slow;
        return app::PlanTrainSweep(sweep, spec, kKeywordNames);
      },
      [&](gearnvh::TrainSweepOptions& options, const TrainSpec& spec, const std::string& source,
          CallControl& control) {
        options.cancel = &control.cancel;
        auto out = std::make_shared<TrainSweep>();
        out->result =
            gearnvh::RunTrainSweep(spec, options, [&](int d, int t) { control.Progress(d, t); });
        out->doc = app::TrainSweepDocument(out->result, spec, source, options);
        return out;
      },
      progress);
}

// speeds x columns of value(point, column); NaN for a failed speed.
template <typename Value>
py::array_t<double> PerSpeed(const gearnvh::TrainSweepResult& r, size_t columns, Value&& value) {
  std::vector<std::vector<double>> rows;
  for (const gearnvh::TrainSweepPoint& p : r.points) {
    std::vector<double> row(columns, std::numeric_limits<double>::quiet_NaN());
    if (p.ok) {
      for (size_t c = 0; c < columns; ++c) row[c] = value(p, c);
    }
    rows.push_back(std::move(row));
  }
  return Matrix(rows);
}

// speeds x loose gears of a loose gear's field, in the order of loose_gear_names (found by name);
// NaN for a failed speed.
py::cpp_function PerSpeedLooseGears(double TrainLooseGearStatistics::*member) {
  return py::cpp_function([member](const TrainSweep& s) {
    const std::vector<std::string>& names = s.result.loose_gear_names;
    return PerSpeed(s.result, names.size(),
                    [&names, member](const gearnvh::TrainSweepPoint& p, size_t g) {
                      const TrainLooseGearStatistics* l = FindLooseGear(p.loose_gears, names[g]);
                      return l ? l->*member : std::numeric_limits<double>::quiet_NaN();
                    });
  });
}

// A (rows x samples) array copied from per-mesh (or per-coupling) histories of one length, as
// `Out`.
template <typename Out, typename In>
py::array_t<Out> MeshMatrix(const std::vector<std::vector<In>>& per_mesh) {
  const size_t rows = per_mesh.size(), columns = rows == 0 ? 0 : per_mesh.front().size();
  py::array_t<Out> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns)});
  auto w = a.template mutable_unchecked<2>();
  for (size_t i = 0; i < rows; ++i) {
    for (size_t k = 0; k < columns; ++k) {
      w(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) =
          static_cast<Out>(per_mesh[i][k]);
    }
  }
  return a;
}

// One field of every logged event, as a 1-D array.
template <typename Out, typename Value>
py::array_t<Out> EventColumn(const TrainHistories& h, Value&& value) {
  py::array_t<Out> a(static_cast<py::ssize_t>(h.events.size()));
  auto w = a.template mutable_unchecked<1>();
  for (size_t i = 0; i < h.events.size(); ++i) {
    w(static_cast<py::ssize_t>(i)) = static_cast<Out>(value(h.events[i]));
  }
  return a;
}

// A read-only view of one of the summary's per-exponent lists.
py::cpp_function LyapunovVector(std::vector<double> TrainLyapunovSummary::*member) {
  return py::cpp_function([member](py::object self) {
    return VectorView(self.cast<const TrainLyapunovSummary&>().*member, self);
  });
}

// TrainHistories: simulate(train, histories=True).histories.
void BindTrainHistories(py::module_& m) {
  py::class_<TrainHistories>(
      m, "TrainHistories",
      "Every mesh's time histories over the recorded cycles of simulate(train, histories=True), "
      "as `simulate --out` writes them (trajectory.csv, events.csv): uniform samples, 32 per "
      "cycle of the fastest mesh, each the exact state at its time. Arrays are copies, meshes (or "
      "couplings) x samples in file order.")
      .def_property_readonly(
          "time",
          [](const TrainHistories& h) {
            const size_t n = h.te.empty() ? 0 : h.te.front().size();
            py::array_t<double> t(static_cast<py::ssize_t>(n));
            auto w = t.mutable_unchecked<1>();
            for (size_t k = 0; k < n; ++k) {
              w(static_cast<py::ssize_t>(k)) = h.start + static_cast<double>(k) * h.dt;
            }
            return t;
          },
          "s")
      .def_property_readonly(
          "te", [](const TrainHistories& h) { return MeshMatrix<double>(h.te); },
          "transmission error, m (meshes x samples)")
      .def_property_readonly(
          "force", [](const TrainHistories& h) { return MeshMatrix<double>(h.force); },
          "mesh force, N (meshes x samples)")
      .def_property_readonly(
          "contact", [](const TrainHistories& h) { return MeshMatrix<int>(h.contact); },
          "contact state: 0 back flank, 1 free, 2 drive flank (as Trajectory.contact)")
      .def_property_readonly(
          "coupling_twist",
          [](const TrainHistories& h) { return MeshMatrix<double>(h.coupling_twist); },
          "each coupling's twist, rad (couplings x samples, file order; as trajectory.csv)")
      .def_property_readonly(
          "coupling_torque",
          [](const TrainHistories& h) { return MeshMatrix<double>(h.coupling_torque); },
          "each coupling's torque k twist + c twist' plus its engaged stages, N m (couplings x "
          "samples)")
      .def_readonly("truncated", &TrainHistories::truncated,
                    "the record held more samples than are kept (4,000,000 per mesh)")
      .def_property_readonly(
          "event_time",
          [](const TrainHistories& h) {
            return EventColumn<double>(h, [](const TrainEventRecord& e) { return e.event.time; });
          },
          "s")
      .def_property_readonly(
          "event_mesh",
          [](const TrainHistories& h) {
            return EventColumn<int>(h, [](const TrainEventRecord& e) { return e.mesh; });
          },
          "the contact's index: the meshes in file order, then each multi-stage coupling's stages "
          "after the first (event_contact_names)")
      .def_readonly("event_contact_names", &TrainHistories::contact_names,
                    "the name of each contact event_mesh indexes")
      .def_property_readonly(
          "event_from",
          [](const TrainHistories& h) {
            return EventColumn<int>(h, [](const TrainEventRecord& e) { return e.event.from; });
          },
          "state before the event")
      .def_property_readonly(
          "event_to",
          [](const TrainHistories& h) {
            return EventColumn<int>(h, [](const TrainEventRecord& e) { return e.event.to; });
          },
          "state after the event")
      .def_property_readonly(
          "event_gap_rate",
          [](const TrainHistories& h) {
            return EventColumn<double>(h,
                                       [](const TrainEventRecord& e) { return e.event.gap_rate; });
          },
          "m/s, the gap's rate crossing its wall (a coupling stage's twist rate: rad/s)")
      .def_readonly("events_truncated", &TrainHistories::events_truncated,
                    "more events than are kept (1,000,000)")
      .def("__repr__", [](const TrainHistories& h) {
        return fmt::format("<gearnvh.TrainHistories {} meshes x {} samples, {} events>",
                           h.te.size(), h.te.empty() ? 0 : h.te.front().size(), h.events.size());
      });
}

}  // namespace

void BindTrain(py::module_& m) {
  py::class_<Train>(m, "Train",
                    "A gear train (schema gearnvh/2): its YAML document and validated input. "
                    "Create with gearnvh.load().")
      .def("set", &Train::Set, py::arg("path"), py::arg("value"),
           "Set a value by schema path ('operating.speed.value', 'meshes[0].backlash', "
           "'operating.loads[1].torque') and revalidate; as Gearbox.set.")
      .def("get", &Train::Get, py::arg("path"),
           "The value at a schema path as written (a str), or the YAML text of a mapping/list.")
      .def(
          "copy", [](const Train& t) { return t; }, "An independent copy.")
      .def("__copy__", [](const Train& t) { return t; })
      .def(
          "__deepcopy__", [](const Train& t, py::dict) { return t; }, py::arg("memo"))
      .def_property_readonly("name", [](const Train& t) { return t.spec().name; })
      .def_property_readonly("source", &Train::source,
                             "The file it came from, '<string>' or '<dict>'.")
      .def_property_readonly(
          "yaml", [](const Train& t) { return t.document().Text(); },
          "The YAML document (re-emitted without comments after set()).")
      .def_property_readonly(
          "meshes",
          [](const Train& t) {
            std::vector<std::string> names;
            for (const TrainMesh& mesh : t.spec().meshes) names.push_back(mesh.Name());
            return names;
          },
          "Mesh names ('gear_a-gear_b'), file order.")
      .def("__repr__", [](const Train& t) {
        return "<gearnvh.Train '" + t.spec().name + "' from " + t.source() + ", " +
               Count(t.spec().meshes.size(), "mesh", "meshes") +
               (t.document().Edited() ? ", edited>" : ">");
      });

  py::class_<TrainMeshStatistics>(m, "MeshResult",
                                  "One mesh of a train run: exact statistics over the record (SI).")
      .def_readonly("name", &TrainMeshStatistics::name)
      .def_readonly("te_mean", &TrainMeshStatistics::te_mean, "m")
      .def_readonly("te_rms", &TrainMeshStatistics::te_rms, "m, about the mean")
      .def_readonly("te_peak_to_peak", &TrainMeshStatistics::te_peak_to_peak, "m")
      .def_readonly("force_mean", &TrainMeshStatistics::force_mean, "N")
      .def_readonly("force_max", &TrainMeshStatistics::force_max, "N")
      .def_readonly("drive_impacts", &TrainMeshStatistics::drive_impacts)
      .def_readonly("back_impacts", &TrainMeshStatistics::back_impacts)
      .def_readonly("separations", &TrainMeshStatistics::separations)
      .def_readonly("grazing", &TrainMeshStatistics::grazing)
      .def_readonly("separation_fraction", &TrainMeshStatistics::free_time_fraction,
                    "fraction of the record out of contact")
      .def_readonly("impact_velocity_rms", &TrainMeshStatistics::impact_velocity_rms, "m/s")
      .def_readonly("impact_velocity_max", &TrainMeshStatistics::impact_velocity_max, "m/s")
      .def("__repr__", [](const TrainMeshStatistics& s) {
        return "<gearnvh.MeshResult " + s.name + ", TE RMS " + std::to_string(s.te_rms * 1e6) +
               " um, " + std::to_string(s.drive_impacts + s.back_impacts) + " impacts>";
      });

  py::class_<TrainLooseGearStatistics>(m, "LooseGearResult",
                                       "A loose gear's rattle in a train run.")
      .def_readonly("name", &TrainLooseGearStatistics::name)
      .def_readonly("rank", &TrainLooseGearStatistics::rank,
                    "1 = largest impact energy per second; 0 = no impact")
      .def_readonly("rattle_index", &TrainLooseGearStatistics::rattle_index,
                    "RMS angular acceleration about the mean, rad/s^2")
      .def_readonly("impacts", &TrainLooseGearStatistics::impacts,
                    "impacts of the meshes this gear belongs to")
      .def_readonly("drive_impacts", &TrainLooseGearStatistics::drive_impacts)
      .def_readonly("back_impacts", &TrainLooseGearStatistics::back_impacts)
      .def_readonly("drive_impacts_per_second", &TrainLooseGearStatistics::drive_impacts_per_second,
                    "1/s")
      .def_readonly("back_impacts_per_second", &TrainLooseGearStatistics::back_impacts_per_second,
                    "1/s")
      .def_readonly("impact_velocity_rms", &TrainLooseGearStatistics::impact_velocity_rms, "m/s")
      .def_readonly("impact_velocity_max", &TrainLooseGearStatistics::impact_velocity_max, "m/s")
      .def_readonly("impact_energy_per_second", &TrainLooseGearStatistics::impact_energy_per_second,
                    "W: (1/2) m_e g'^2 summed over the impacts, per recorded second")
      .def("__repr__", [](const TrainLooseGearStatistics& g) {
        return "<gearnvh.LooseGearResult " + (g.rank > 0 ? std::to_string(g.rank) + ". " : "- ") +
               g.name + ", " + std::to_string(g.impact_energy_per_second) + " W, " +
               std::to_string(g.impacts) + " impacts>";
      });

  py::class_<TrainLyapunovSummary>(
      m, "TrainLyapunov",
      "The largest Lyapunov exponents of a train run (simulate(train, lyapunov=K)): exact "
      "tangents with a saltation per gap event, the free rotation projected out.")
      .def_property_readonly(
          "status", [](const TrainLyapunovSummary& l) { return TrainLyapunovInfoName(l.info); })
      .def_property_readonly("ok",
                             [](const TrainLyapunovSummary& l) {
                               return l.info == TrainLyapunovSummary::Info::kSuccess;
                             })
      .def_readonly("message", &TrainLyapunovSummary::message)
      .def_property_readonly("exponents", LyapunovVector(&TrainLyapunovSummary::exponents),
                             "1/s, largest first")
      .def_property_readonly("standard_errors",
                             LyapunovVector(&TrainLyapunovSummary::standard_errors),
                             "1/s, block standard error of each exponent")
      .def_property_readonly("per_forcing_cycle",
                             LyapunovVector(&TrainLyapunovSummary::per_forcing_cycle), "lambda T_f")
      .def_property_readonly("per_mesh_cycle",
                             LyapunovVector(&TrainLyapunovSummary::per_mesh_cycle),
                             "lambda T_1 (the first mesh)")
      .def_readonly("forcing_period_s", &TrainLyapunovSummary::forcing_period)
      .def_readonly("mesh_period_s", &TrainLyapunovSummary::mesh_period)
      .def_readonly("averaged_s", &TrainLyapunovSummary::averaged_s, "time averaged, s")
      .def_readonly("saltations", &TrainLyapunovSummary::saltations)
      .def_readonly("predictability_horizon_s", &TrainLyapunovSummary::predictability_horizon_s,
                    "52 ln 2 / lambda_1; inf when lambda_1 <= 0")
      .def_readonly("predictability_horizon_cycles",
                    &TrainLyapunovSummary::predictability_horizon_cycles, "forcing cycles")
      .def("__repr__", [](const TrainLyapunovSummary& l) {
        return "<gearnvh.TrainLyapunov " + std::to_string(l.exponents.size()) +
               " exponents, largest " +
               (l.exponents.empty() ? std::string("-") : std::to_string(l.exponents.front())) +
               " 1/s>";
      });

  BindTrainHistories(m);

  py::class_<TrainSimulation, std::shared_ptr<TrainSimulation>>(
      m, "TrainSimulation", "One operating point of a gear train (gearnvh simulate TRAIN.yaml).")
      .def_property_readonly(
          "meshes", [](const TrainSimulation& s) { return s.op.stats.meshes; },
          "MeshResult per mesh, file order")
      .def_property_readonly(
          "loose_gears", [](const TrainSimulation& s) { return s.op.stats.loose_gears; },
          "LooseGearResult per loose gear, by rank (1 = the largest impact energy), then the gears "
          "without impacts (rank 0)")
      .def_property_readonly(
          "sidebands",
          [](const TrainSimulation& s) {
            py::dict out;
            for (size_t i = 0; i < s.op.sidebands.size(); ++i)
              out[py::str(s.op.tables.meshes[i].name)] = s.op.sidebands[i].rows;
            return out;
          },
          "mesh name -> the TE spectrum lines that stand out (Sideband list)")
      .def_property_readonly("warnings", [](const TrainSimulation& s) { return s.op.warnings; })
      .def_property_readonly(
          "events", [](const TrainSimulation& s) { return s.op.summary.events; },
          "contact events of the whole run")
      .def_property_readonly("real_time_ratio",
                             [](const TrainSimulation& s) {
                               return s.op.wall_s > 0.0 ? s.op.summary.simulated_time / s.op.wall_s
                                                        : 0.0;
                             })
      .def_property_readonly(
          "lyapunov",
          [](py::object self) -> py::object {
            const TrainSimulation& s = self.cast<const TrainSimulation&>();
            if (!s.lyapunov) return py::none();
            return py::cast(*s.lyapunov, py::return_value_policy::reference_internal, self);
          },
          "TrainLyapunov with lyapunov=K, else None")
      .def_property_readonly(
          "histories",
          [](py::object self) -> py::object {
            const TrainSimulation& s = self.cast<const TrainSimulation&>();
            if (s.op.histories.dt <= 0.0) return py::none();
            return py::cast(s.op.histories, py::return_value_policy::reference_internal, self);
          },
          "TrainHistories with histories=True, else None")
      .def_property_readonly(
          "ok",
          [](const TrainSimulation& s) {
            return s.op.ok() &&
                   (!s.lyapunov || s.lyapunov->info == TrainLyapunovSummary::Info::kSuccess);
          })
      .def(
          "to_dict", [](const TrainSimulation& s) { return ToPython(s.doc); },
          "The document `gearnvh simulate --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainSimulation& s) {
        return "<gearnvh.TrainSimulation " + std::to_string(s.op.stats.meshes.size()) +
               " meshes, " + std::to_string(s.op.summary.events) + " events>";
      });

  py::class_<TrainSweep, std::shared_ptr<TrainSweep>>(
      m, "TrainSweep", "A train's speed sweep (gearnvh sweep TRAIN.yaml); arrays are speeds x ...")
      .def_property_readonly("speeds_rpm",
                             [](const TrainSweep& s) {
                               std::vector<double> v;
                               for (const auto& p : s.result.points) v.push_back(p.speed_rpm);
                               return py::array_t<double>(static_cast<py::ssize_t>(v.size()),
                                                          v.data());
                             })
      .def_property_readonly(
          "ok",
          [](const TrainSweep& s) {
            return PerRow(s.result.points, [](const auto& p) { return p.ok; });
          },
          "per speed: the run finished")
      .def_property_readonly(
          "messages",
          [](const TrainSweep& s) {
            return PerRow(s.result.points, [](const auto& p) { return p.message; });
          },
          "per speed: why the run failed ('' when it did not)")
      .def_property_readonly("mesh_names", [](const TrainSweep& s) { return s.result.mesh_names; })
      .def_property_readonly("loose_gear_names",
                             [](const TrainSweep& s) { return s.result.loose_gear_names; })
      .def_property_readonly(
          "te_rms",
          [](const TrainSweep& s) {
            return PerSpeed(
                s.result, s.result.mesh_names.size(),
                [](const gearnvh::TrainSweepPoint& p, size_t i) { return p.meshes[i].te_rms; });
          },
          "speeds x meshes, m (NaN for a failed speed)")
      .def_property_readonly(
          "force_max",
          [](const TrainSweep& s) {
            return PerSpeed(
                s.result, s.result.mesh_names.size(),
                [](const gearnvh::TrainSweepPoint& p, size_t i) { return p.meshes[i].force_max; });
          },
          "speeds x meshes, N")
      .def_property_readonly(
          "impacts_per_cycle",
          [](const TrainSweep& s) {
            return PerSpeed(
                s.result, s.result.mesh_names.size(),
                [](const gearnvh::TrainSweepPoint& p, size_t i) { return p.ImpactsPerCycle(i); });
          },
          "speeds x meshes: drive + back impacts per cycle of that mesh")
      .def_property_readonly("rattle_index",
                             PerSpeedLooseGears(&TrainLooseGearStatistics::rattle_index),
                             "speeds x loose gears (in the order of loose_gear_names), rad/s^2 "
                             "(RMS angular acceleration)")
      .def_property_readonly(
          "impact_energy_per_second",
          PerSpeedLooseGears(&TrainLooseGearStatistics::impact_energy_per_second),
          "speeds x loose gears (in the order of loose_gear_names), W")
      .def(
          "to_dict", [](const TrainSweep& s) { return ToPython(s.doc); },
          "The document `gearnvh sweep --json TRAIN.yaml` prints.")
      .def("__repr__", [](const TrainSweep& s) {
        const auto& p = s.result.points;
        return fmt::format(
            "<gearnvh.TrainSweep {} speeds{}, {} meshes, {} failed>", p.size(),
            p.empty() ? std::string()
                      : fmt::format(" {:.4g}-{:.4g} rpm", p.front().speed_rpm, p.back().speed_rpm),
            s.result.mesh_names.size(), s.result.failed());
      });

  m.def("check", &CheckTrain, py::arg("gearbox"),
        "Validate and describe a gear train: the document of `gearnvh check --json TRAIN.yaml` "
        "(bodies, meshes, modes, tiers, Campbell data; SI units).");
  m.def("simulate", &SimulateTrain, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("cycles") = py::none(), py::arg("transient") = py::none(), py::arg("method") = "v3",
        py::arg("lyapunov") = py::none(), py::arg("histories") = false,
        py::arg("allow_slow") = false, py::arg("progress") = py::none(),
        "A gear train's operating point, as `gearnvh simulate TRAIN.yaml`: cycles and transient "
        "count cycles of the first mesh (default analysis.cycles, analysis.transient_cycles); "
        "method: v1, v2, v3 (fused means v3 on trains); lyapunov=K: also the K largest Lyapunov "
        "exponents (a second run, as --lyapunov K); histories: keep every mesh's TE, force and "
        "contact at every sample and the event log (TrainSimulation.histories, as --out); "
        "allow_slow: run even when the run-cost "
        "estimate exceeds one hour (as --allow-slow; refused otherwise).");
  m.def("sweep", &SweepTrain, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("cycles") = py::none(), py::arg("transient") = py::none(), py::arg("jobs") = 0,
        py::arg("method") = "v3", py::arg("allow_slow") = false, py::arg("progress") = py::none(),
        "A gear train's speed sweep over analysis.speed_sweep, as `gearnvh sweep TRAIN.yaml` "
        "(allow_slow as simulate's).");
}

}  // namespace gearnvh::python
