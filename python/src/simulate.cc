// gearnvh.simulate(): one operating point through the exact solver (the library call behind
// `gearnvh simulate`), with the trajectory, events and spectrum as NumPy views.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "binding_support.h"
#include "gearbox.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/lyapunov.h"
#include "result_documents.h"
#include "simulate_command.h"

namespace gearnvh::python {

namespace {

struct Simulation {
  gearnvh::OperatingPointAnalysis op;
  double rattle_index = 0.0;  // impact energy per forcing cycle, J (as atlas and tiers)
  nlohmann::json doc;         // the `simulate --json` document
};

std::shared_ptr<Simulation> Simulate(const Gearbox& gb, const py::object& tier,
                                     std::optional<long> cycles, std::optional<long> transient,
                                     const std::string& method, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  const Tier chosen = TierArgument(tier, spec.analysis.tier, source);
  SolverOptions solver;
  solver.cycles = cycles.value_or(spec.analysis.cycles);
  solver.transient_cycles = transient.value_or(spec.analysis.transient_cycles);
  ApplyLadderMethod(NamingSource(source, [&] { return app::ParseMethod(method, "method"); }),
                    solver);
  NamingSource(source, [&] {
    solver.Validate();
    RequirePairRunLength(spec, spec.operating.speed, solver.cycles, solver.transient_cycles, cycles,
                         transient, true);
  });
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] {
          SolverOptions run = solver;
          run.cancel = &control.cancel;
          const ComponentModel model = BuildComponentModel(spec);
          auto out = std::make_shared<Simulation>();
          // The command line's memory check (docs/cli.md, "Memory"), at the keyword or the file's
          // analysis.cycles.
          const std::string cycles_at =
              cycles ? kKeywordNames("cycles") : std::string("analysis.cycles");
          out->op = gearnvh::AnalyseOperatingPoint(
              spec, model, chosen, run, [&](long d, long t) { control.Progress(d, t); }, {},
              [&](RunMemory& need) {
                return CheckRunMemory(need, AvailableMemory(), cycles_at,
                                      std::to_string(run.cycles));
              });
          out->op.solver.cancel = nullptr;  // the flag dies with this call
          const SegmentTables& tables = out->op.tables;
          out->rattle_index =
              out->op.rattle.impact_energy_per_cycle * ForcingPeriod(tables) / tables.mesh_period;
          out->doc = app::OperatingPointJson(out->op);
          out->doc["name"] = spec.name;
          out->doc["file"] = source;
          return out;
        });
      },
      progress);
}

template <typename Field>
py::cpp_function SampleField(Field TrajectorySample::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Trajectory&>().samples, member, self);
  });
}

template <typename Field>
py::cpp_function EventField(Field EventRecord::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Trajectory&>().events, member, self);
  });
}

}  // namespace

void BindSimulate(py::module_& m) {
  py::class_<Trajectory>(
      m, "Trajectory",
      "The recorded window of a run: uniform samples (32 per mesh cycle, each the exact state at "
      "its time) and contact events. Every attribute is a read-only NumPy view of the C++ "
      "arrays (no copy).")
      .def("__len__", [](const Trajectory& t) { return t.samples.size(); })
      .def_property_readonly("time", SampleField(&TrajectorySample::time), "s")
      .def_property_readonly("te", SampleField(&TrajectorySample::te),
                             "dynamic transmission error, m")
      .def_property_readonly("te_rate", SampleField(&TrajectorySample::te_rate), "m/s")
      .def_property_readonly("force", SampleField(&TrajectorySample::mesh_force),
                             "mesh force, N (positive on the drive flank)")
      .def_property_readonly("pinion_speed", SampleField(&TrajectorySample::pinion_speed),
                             "angular velocity perturbation, rad/s")
      .def_property_readonly("wheel_speed", SampleField(&TrajectorySample::wheel_speed), "rad/s")
      .def_property_readonly("wheel_acceleration",
                             SampleField(&TrajectorySample::wheel_acceleration), "rad/s^2")
      .def_property_readonly("contact", SampleField(&TrajectorySample::state),
                             "contact state per sample: 0 back flank, 1 free, 2 drive flank")
      .def_property_readonly("event_time", EventField(&EventRecord::time), "s")
      .def_property_readonly("event_from", EventField(&EventRecord::from),
                             "state before the event (0 back, 1 free, 2 drive)")
      .def_property_readonly("event_to", EventField(&EventRecord::to), "state after the event")
      .def_property_readonly("event_gap_rate", EventField(&EventRecord::gap_rate),
                             "m/s, rate of the gap crossing its wall")
      .def("__repr__", [](const Trajectory& t) {
        const double span =
            t.samples.empty() ? 0.0 : t.samples.back().time - t.samples.front().time;
        return fmt::format("<gearnvh.Trajectory {} samples over {:.4g} s, {} events>",
                           t.samples.size(), span, t.events.size());
      });

  py::class_<SolverSummary>(m, "SolverSummary", "The solver's account of a run (SI units).")
      .def_property_readonly("status",
                             [](const SolverSummary& s) { return SolverStatusName(s.status); })
      .def_readonly("message", &SolverSummary::message)
      .def_readonly("mesh_cycles", &SolverSummary::mesh_cycles, "recorded + transient")
      .def_readonly("events", &SolverSummary::events)
      .def_readonly("drive_impacts", &SolverSummary::drive_impacts)
      .def_readonly("back_impacts", &SolverSummary::back_impacts)
      .def_readonly("separations", &SolverSummary::separations)
      .def_readonly("grazing", &SolverSummary::grazing)
      .def_readonly("events_per_cycle", &SolverSummary::events_per_cycle)
      .def_readonly("matvecs", &SolverSummary::matvecs)
      .def_readonly("matvec_per_cycle", &SolverSummary::matvec_per_cycle)
      .def_readonly("fused_cycles", &SolverSummary::fused_cycles)
      .def_readonly("jumped_cycles", &SolverSummary::jumped_cycles)
      .def_readonly("contact_certified", &SolverSummary::contact_certified)
      .def_readonly("simulated_s", &SolverSummary::simulated_s)
      .def_readonly("wall_s", &SolverSummary::wall_s, "wall-clock time of the exact run, s")
      .def_readonly("real_time_ratio", &SolverSummary::real_time_ratio,
                    "simulated time / wall time")
      .def_readonly("table_bytes", &SolverSummary::table_bytes)
      .def_readonly("trajectory_truncated", &SolverSummary::trajectory_truncated)
      .def("__repr__", [](const SolverSummary& s) {
        return fmt::format(
            "<gearnvh.SolverSummary {}, {} mesh cycles, {} events, {:.3g} x real time>",
            SolverStatusName(s.status), s.mesh_cycles, s.events, s.real_time_ratio);
      });

  py::class_<TransmissionErrorStats>(m, "TeStats", "TE statistics over the recorded window (SI).")
      .def_readonly("mean", &TransmissionErrorStats::mean, "m")
      .def_readonly("mean_from_contact", &TransmissionErrorStats::mean_from_contact,
                    "m, mean - half backlash")
      .def_readonly("rms", &TransmissionErrorStats::rms, "m, about the mean")
      .def_readonly("peak_to_peak", &TransmissionErrorStats::peak_to_peak, "m")
      .def_readonly("max", &TransmissionErrorStats::max, "m")
      .def_readonly("min", &TransmissionErrorStats::min, "m")
      .def_readonly("mesh_force_mean", &TransmissionErrorStats::mesh_force_mean, "N")
      .def_readonly("mesh_force_max", &TransmissionErrorStats::mesh_force_max, "N")
      .def_readonly("dynamic_factor", &TransmissionErrorStats::dynamic_factor,
                    "max mesh force / static mesh force")
      .def("__repr__", [](const TransmissionErrorStats& s) {
        return fmt::format("<gearnvh.TeStats RMS {:.4g} um, p-p {:.4g} um, dynamic factor {:.4g}>",
                           s.rms * 1e6, s.peak_to_peak * 1e6, s.dynamic_factor);
      });

  py::class_<RattleIndices>(m, "Rattle", "Rattle indices of a run (docs/results.md).")
      .def_property_readonly("regime",
                             [](const RattleIndices& r) { return RattleRegimeName(r.regime); })
      .def_readonly("drive_impacts_per_cycle", &RattleIndices::drive_impacts_per_cycle)
      .def_readonly("back_impacts_per_cycle", &RattleIndices::back_impacts_per_cycle)
      .def_readonly("drive_impacts_per_second", &RattleIndices::drive_impacts_per_second, "1/s")
      .def_readonly("back_impacts_per_second", &RattleIndices::back_impacts_per_second, "1/s")
      .def_readonly("impact_velocity_rms", &RattleIndices::impact_velocity_rms, "m/s")
      .def_readonly("impact_velocity_max", &RattleIndices::impact_velocity_max, "m/s")
      .def_readonly("impact_energy_per_cycle", &RattleIndices::impact_energy_per_cycle,
                    "J per mesh cycle")
      .def_readonly("impact_energy_per_second", &RattleIndices::impact_energy_per_second,
                    "W, as a train's loose gear's")
      .def_readonly("separation_fraction", &RattleIndices::separation_fraction)
      .def_readonly("wheel_acceleration_rms", &RattleIndices::wheel_acceleration_rms, "rad/s^2")
      .def_readonly("acceleration_ratio", &RattleIndices::acceleration_ratio,
                    "wheel acceleration RMS / the same gearbox without backlash")
      .def("__repr__", [](const RattleIndices& r) {
        return fmt::format("<gearnvh.Rattle {}, {:.4g} drive / {:.4g} back impacts per cycle>",
                           RattleRegimeName(r.regime), r.drive_impacts_per_cycle,
                           r.back_impacts_per_cycle);
      });

  py::class_<AmplitudeSpectrum>(m, "Spectrum", "Hann amplitude spectrum of the TE.")
      .def_readonly("bin_hz", &AmplitudeSpectrum::bin_hz)
      .def_property_readonly(
          "amplitude",
          [](py::object self) {
            return VectorView(self.cast<const AmplitudeSpectrum&>().amplitude, self);
          },
          "m per bin (view)")
      .def_property_readonly(
          "frequency_hz",
          [](const AmplitudeSpectrum& s) {
            py::array_t<double> f(static_cast<py::ssize_t>(s.amplitude.size()));
            for (py::ssize_t k = 0; k < f.size(); ++k) f.mutable_at(k) = k * s.bin_hz;
            return f;
          },
          "Hz per bin")
      .def("__repr__", [](const AmplitudeSpectrum& s) {
        return fmt::format("<gearnvh.Spectrum {} bins of {:.4g} Hz>", s.amplitude.size(), s.bin_hz);
      });

  py::class_<SidebandRow>(m, "Sideband", "A mesh harmonic, shaft order or sideband of the TE.")
      .def_readonly("label", &SidebandRow::label)
      .def_readonly("frequency_hz", &SidebandRow::frequency_hz)
      .def_readonly("amplitude", &SidebandRow::amplitude, "m")
      .def_readonly("db_re_1um", &SidebandRow::db_re_1um, "dB re 1 µm")
      .def_readonly("background", &SidebandRow::background, "m, local median")
      .def("__repr__", [](const SidebandRow& r) {
        return "<Sideband " + r.label + " " + std::to_string(r.frequency_hz) + " Hz>";
      });

  const auto internal = py::return_value_policy::reference_internal;
  py::class_<Simulation, std::shared_ptr<Simulation>>(
      m, "Simulation", "One operating point through the exact solver (gearnvh simulate).")
      .def_property_readonly(
          "te", [](const Simulation& s) -> const auto& { return s.op.te; }, internal,
          "TeStats: mean, rms, peak_to_peak, ... (m)")
      .def_property_readonly(
          "summary", [](const Simulation& s) -> const auto& { return s.op.result.summary; },
          internal, "SolverSummary: events, matvecs, wall_s, real_time_ratio, ...")
      .def_property_readonly(
          "rattle", [](const Simulation& s) -> const auto& { return s.op.rattle; }, internal)
      .def_readonly("rattle_index", &Simulation::rattle_index,
                    "impact energy per forcing (rattle) cycle, J: the atlas's rattle index")
      .def_property_readonly(
          "trajectory", [](const Simulation& s) -> const auto& { return s.op.result.trajectory; },
          internal, "Trajectory: NumPy views of time, te, force, ...")
      .def_property_readonly(
          "spectrum", [](const Simulation& s) -> const auto& { return s.op.spectrum; }, internal,
          "TE Spectrum over the sideband window (empty when the record holds no whole period)")
      .def_property_readonly("sidebands", [](const Simulation& s) { return s.op.sidebands; })
      .def_property_readonly("warnings", [](const Simulation& s) { return s.op.warnings; })
      .def_property_readonly("tier", [](const Simulation& s) { return s.op.tier_name; })
      .def_property_readonly("state_dim", [](const Simulation& s) { return s.op.tables.m; })
      .def_property_readonly(
          "cycles", [](const Simulation& s) { return s.op.result.summary.recorded_cycles; },
          "mesh cycles recorded (rounded up to whole periods when needed; fewer when the run "
          "stopped)")
      .def_property_readonly(
          "ok",
          [](const Simulation& s) { return s.op.result.summary.status == SolverStatus::kSuccess; })
      .def(
          "to_dict", [](const Simulation& s) { return ToPython(s.doc); },
          "The document `gearnvh simulate --json` prints.")
      .def("__repr__", [](const Simulation& s) {
        return "<gearnvh.Simulation " + s.op.tier_name + ", TE RMS " +
               std::to_string(s.op.te.rms * 1e6) + " um, " + RattleRegimeName(s.op.rattle.regime) +
               ">";
      });

  m.def("simulate", &Simulate, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("cycles") = py::none(), py::arg("transient") = py::none(),
        py::arg("method") = "fused", py::arg("progress") = py::none(),
        "One operating point through the exact solver, as `gearnvh simulate`. tier: 1..5, "
        "'N40 full', 'N20 simple', 'N20 MTA' (default analysis.tier); cycles, transient: mesh "
        "cycles (default analysis.cycles, analysis.transient_cycles); method: v1, v2, v3, fused; "
        "progress: optional callable(done, total). Releases the GIL; Ctrl-C interrupts.");
}

}  // namespace gearnvh::python
