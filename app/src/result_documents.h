// The JSON and text of analysis results that several commands, the report and the Python module
// share: SI units in JSON, as docs/cli.md lists the keys.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_statistics.h"

namespace gearnvh::app {

// Printed under a stopped run's status in the text of `simulate`: what follows is not a result.
inline constexpr const char* kStoppedRunNote =
    "(the numbers below are of the part run before the stop, not results)";

// {"bytes": total, "parts": {name: bytes}}: the `memory_estimate` of a results document.
nlohmann::json MemoryJson(const RunMemory& memory);

nlohmann::json SummaryJson(const SolverSummary& s);

// The `simulate --json` document of a pair's operating point without name and file.
nlohmann::json OperatingPointJson(const OperatingPointAnalysis& op);

// `tier_adequacy`: the verdict, the frequency limit and each mode the meshes see; with
// `mesh_names` (a train's, file order) each mode names the mesh that sees it most.
nlohmann::json TierAdequacyJson(const TierAdequacy& adequacy, const TierAdequacyOptions& options,
                                const std::vector<std::string>& mesh_names);

// The mesh harmonics of a TE sideband table on one line, as `simulate` prints them: "1 fm: 0.1234
// µm  2 fm: 0.0123 µm  " (a table holds up to hundreds of shaft-order lines and sidebands, down
// to the rounding floor: those are in --json). Empty when no harmonic stands out.
std::string MeshHarmonicsText(const std::vector<SidebandRow>& rows);

// What the TE mean contains: half the backlash b (delta is measured from the nominal rigid
// rotation, and drive contact closes the gap at delta = b), and the mean from the contact.
std::string TeMeanNote(const TransmissionErrorStats& te, double half_backlash);

// Why the dynamic factor may not be meaningful: "" under load; a note when the mean mesh force is
// near zero next to its peaks (drag torque, rattle), where max / static force is large by
// construction.
std::string DynamicFactorNote(const TransmissionErrorStats& te);

// `meshes` and `loose_gears` of `simulate --json` on a train (docs/cli.md), SI units.
nlohmann::json TrainMeshesJson(const TrainOperatingPoint& op);
nlohmann::json TrainLooseGearsJson(const std::vector<TrainLooseGearStatistics>& gears);
// "input.bearings[0]", or "input support" for a shaft's default support (index -1).
std::string BearingName(const std::string& shaft, int index);
// simulate's `bearings`: per bearing its name, shaft, index, position, and in x, y, z the mean and
// RMS force on the housing and the amplitude at each mesh harmonic (TrainBearingForce).
nlohmann::json TrainBearingForcesJson(const TrainOperatingPoint& op, const TrainSpec& spec);
// simulate's (and each sweep point's) `couplings`: per coupling its name and the exact mean, RMS,
// min and max of its twist (rad) and torque (N m) over the record (TrainCouplingResponse).
nlohmann::json TrainCouplingsJson(const std::vector<TrainCouplingResponse>& couplings,
                                  double recorded_s);
nlohmann::json SidebandsJson(const std::vector<SidebandRow>& rows);

}  // namespace gearnvh::app
