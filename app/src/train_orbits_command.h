// `gearnvh orbits` on a gear train (schema gearnvh/2): period-M orbits (M common periods of the
// train) by Newton shooting on the exact train flow (nvh/train_orbit_scan.h), at the file's
// operating point or along one train parameter (`--sweep`, config/train_parameters.h); Floquet
// multipliers on the quotient by the free rotation, stability, text and JSON (docs/cli.md).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/train_orbit_scan.h"
#include "orbits_command.h"

namespace gearnvh::app {

// What `orbits` runs on a train, from its options (the command line's or the Python module's,
// `names` saying how they are named in errors): the scan's options (--period, --transient default
// analysis.transient_cycles, tier, event method) and the swept parameter with its values (one
// point at the operating point without --sweep). Throws InputError naming the option or key.
struct TrainOrbitsPlan {
  TrainOrbitScanOptions scan;
  std::optional<AtlasAxis> sweep;
  std::string sweep_option;    // the option's name for a variant's error
  std::vector<double> values;  // SI, one per point (0 without a sweep)
  bool allow_slow = false;     // run even when the cost estimate exceeds an hour
  OptionNames names;
};
TrainOrbitsPlan PlanTrainOrbits(const OrbitsCommandOptions& options, const TrainSpec& spec,
                                const OptionNames& names = {});
// The scan's run-cost check before any point runs (CheckRunCost): per point the transient and one
// shot over the orbit's period at the file's operating point (a lower bound: Newton takes several
// shots, each with tangent columns), points one after another. Returns the warning (empty when
// none); throws InputError naming names("allow-slow") when refused.
std::string CheckTrainOrbitsCost(const TrainSpec& spec, const TrainOrbitsPlan& plan);

// The plan's points (ScanTrainPeriodicOrbits over the variants).
std::vector<TrainOrbitScanPoint> RunTrainOrbits(const TrainSpec& spec, const TrainOrbitsPlan& plan,
                                                const TrainOrbitScanProgress& progress = {});

// `orbits --json` on a train (docs/results.md, "Periodic orbits of a train").
nlohmann::json TrainOrbitsDocument(const std::vector<TrainOrbitScanPoint>& points,
                                   const TrainOrbitsPlan& plan, const TrainSpec& spec,
                                   const std::string& file);

int OrbitsTrain(const OrbitsCommandOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
