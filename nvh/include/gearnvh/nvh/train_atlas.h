// One cell of a gear train's chaos atlas (docs/gear-trains.md, "Atlas and orbits of a train"):
// a train variant (schema gearnvh/2, tier 1) taken through its tables and one settled exact run
// with tangents (train_lyapunov.h) that also records its statistics (train_statistics.h):
//   the largest Lyapunov exponent of the quotient by the free rotation (1/s, per forcing cycle,
//   standard error), per mesh its impacts per mesh cycle on each flank, separation fraction,
//   impact velocity RMS and regime, per loose gear its rattle index (RMS angular acceleration).
// Regimes are the pair's rules (rattle.h): a mesh is kNoImpact / kSingleSided / kDoubleSided from
// its own impacts over the recorded cycles; the train's regime is the mesh regime of the most
// impacts-sided mesh (double > single > none), replaced by kChaotic when the train's largest
// exponent passes IsChaotic with the pair's threshold (lambda T_f > 0.01 and lambda > 3 standard
// errors, T_f the first engine order's period, the first mesh's without excitation). The train
// has one largest exponent, so chaos is a property of the whole train, not of one mesh.
// Which parameter a cell varies is the caller's business: the cell takes the variant itself.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

struct TrainAtlasOptions {
  long transient_cycles = 300;    // cycles of the first mesh settled before measuring; >= 0
  long cycles = 1080;             // cycles of the first mesh averaged; >= 8
  double chaos_threshold = 0.01;  // lambda T_f above which a cell is chaotic (the pair's); > 0
  EventMethod events = EventMethod::kSpectral;
  Tier tier = Tier::kTier1;  // the train solver's tier (BuildTrainTablesAtTier)
  // Passed to the run (TrainStepperOptions::cancel): a cancelled cell fails with "cancelled".
  // Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  // How an input error of a cell's variant is worded (RunTrainAtlas, analysis/train_atlas.h),
  // given the parameters the variant was set to, as AtlasOptions::input_error_message. Empty:
  // what().
  std::function<std::string(const InputError&, const std::vector<ParameterValue>&)>
      input_error_message;
  void Validate() const;  // throws InputError naming the field
};

struct TrainAtlasMesh {
  std::string name;
  double drive_impacts_per_cycle = 0.0, back_impacts_per_cycle = 0.0;  // per cycle of this mesh
  double separation_fraction = 0.0;
  double impact_velocity_rms = 0.0;  // m/s
  RattleRegime regime = RattleRegime::kNoImpact;
};

struct TrainAtlasLooseGear {
  std::string name;
  double rattle_index = 0.0;  // RMS angular acceleration about the mean, rad/s^2
  long impacts = 0;           // impacts of its meshes over the recorded cycles
  int rank = 0;  // 1 = largest impact energy per second in this cell; 0 = no impact
  double impact_energy_per_second = 0.0;  // W (TrainLooseGearStatistics)
};

struct TrainAtlasPoint {
  bool ok = false;
  std::string message;  // why the point failed
  double lyapunov_per_s = 0.0, lyapunov_per_forcing_cycle = 0.0, lyapunov_standard_error = 0.0;
  RattleRegime regime = RattleRegime::kNoImpact;
  std::vector<TrainAtlasMesh> meshes;            // file order
  std::vector<TrainAtlasLooseGear> loose_gears;  // by rank
  double wall_s = 0.0;
};

// Builds the component model of a variant (BuildGearTrain, or a train built once and moved to the
// variant's speed by GearTrainAtSpeed).
using TrainBuilder = std::function<GearTrain(const TrainSpec& variant)>;

// One variant; never throws (a failure, including an invalid variant, is reported in the point).
// `build` empty: BuildGearTrain.
TrainAtlasPoint ComputeTrainAtlasPoint(const TrainSpec& variant, const TrainAtlasOptions& options,
                                       const TrainBuilder& build = {});

}  // namespace gearnvh
