// `sweep` on a gear train: its options checked and planned (the command line's or the Python
// module's), and the sweep's documents (JSON in SI units, CSV, the terminal's tables).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "display_units.h"
#include "gearnvh/analysis/option_names.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/model/train_spec.h"
#include "sweep_command.h"

namespace gearnvh::app {

// What `sweep` runs on a train, from its options (the command line's or the Python module's,
// `names` saying how they are named in errors): --cycles (default 512), --transient (200),
// --jobs, tier and event method, held to the run-length limit at the sweep's lowest speed.
TrainSweepOptions PlanTrainSweep(const SweepOptions& options, const TrainSpec& spec,
                                 const OptionNames& names = {});

// The sweep's documents: JSON (SI units) and CSV, one row per speed and mesh / loose gear.
nlohmann::json TrainSweepJson(const TrainSweepResult& r);
// One speed with everything the outputs read from it (statistics, waterfall rows), and back
// (throws on a missing or mistyped field): the form MPI ranks exchange. Numbers round-trip bit for
// bit.
nlohmann::json TrainSweepPointJson(const TrainSweepPoint& p);
TrainSweepPoint TrainSweepPointFromJson(const nlohmann::json& j);
// `sweep --json` on a train: TrainSweepJson with the train's name, the file, the tier, and the
// cycles and transient per speed.
nlohmann::json TrainSweepDocument(const TrainSweepResult& r, const TrainSpec& spec,
                                  const std::string& file, const TrainSweepOptions& options);
std::string TrainMeshesCsv(const TrainSweepResult& r);
std::string TrainLooseGearsCsv(const TrainSweepResult& r);
// Per speed whose run succeeded and coupling (file order) its twist (rad) and torque (N m): mean,
// RMS, min, max (exact, TrainCouplingResponse); the header only without couplings.
std::string TrainCouplingsCsv(const TrainSweepResult& r);
// (waterfall.csv: WaterfallCsv of MeshWaterfalls, sweep_command.h.)

// Prints the sweep's text tables (per mesh, then the loose gears' impact energy and rank per speed).
// The tables of a sweep on a terminal, speeds in `speed_unit` (the unit the file wrote).
void PrintTrainSweep(const TrainSweepResult& r, const DisplayUnit& speed_unit);

}  // namespace gearnvh::app
