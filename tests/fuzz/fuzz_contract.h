// The contract the loader fuzzer checks (tests/fuzz/loader_fuzzer.cc) and the regression test
// replays (tests/app/fuzz_regressions_test.cc): any text either loads, as either schema, into a
// spec whose models are finite — a pair's geometry and component model (mesh stiffness over the
// cycle, load sharing, LSTE, FE matrices); a train's mesh models, tier-1 torsional modes and
// structural matrices — or throws InputError.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_structure.h"

namespace gearnvh::fuzz {

enum class Outcome { kLoaded, kInputError };

// A non-finite model quantity: a defect (thrown as a logic_error naming the quantity).
inline void RequireFinite(double v, const char* what) {
  if (!std::isfinite(v)) throw std::logic_error(std::string("not finite: ") + what);
}

inline void RequireFiniteStiffness(const MeshStiffnessSummary& k) {
  RequireFinite(k.mean, "mesh stiffness mean");
  RequireFinite(k.min, "mesh stiffness min");
  RequireFinite(k.max, "mesh stiffness max");
  RequireFinite(k.lste_peak_to_peak, "LSTE peak-to-peak");
  RequireFinite(k.load_sharing_max, "load sharing");
}

inline void CheckPair(const GearboxSpec& spec) {
  const PairGeometry g = ComputePairGeometry(spec);
  RequireFinite(g.contact_ratio, "contact ratio");
  RequireFinite(g.center_distance, "centre distance");
  const ComponentModel model = BuildComponentModel(spec);
  RequireFiniteStiffness(model.mesh_summary);
  if (!model.K.coeffs().allFinite() || !model.M.coeffs().allFinite())
    throw std::logic_error("not finite: FE matrices");
}

inline void CheckTrain(const TrainSpec& spec) {
  const GearTrain train = BuildGearTrain(spec);
  for (const TrainMeshModel& mesh : train.meshes) {
    RequireFinite(mesh.geometry.contact_ratio, "contact ratio");
    RequireFiniteStiffness(mesh.stiffness);
    RequireFinite(mesh.transmitted_torque, "transmitted torque");
  }
  const TrainTorsionalModes modes = TorsionalModes(train);
  for (double f : modes.frequencies_hz) RequireFinite(f, "torsional natural frequency");
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  if (!structure.K.coeffs().allFinite() || !structure.M.coeffs().allFinite())
    throw std::logic_error("not finite: train structural matrices");
}

inline Outcome CheckInput(const std::string& text, const std::string& source) {
  try {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(text, source);
    if (loaded.schema == 1) {
      CheckPair(*loaded.pair);
    } else {
      CheckTrain(loaded.train);
    }
    return Outcome::kLoaded;
  } catch (const InputError&) {
    return Outcome::kInputError;
  }
}

}  // namespace gearnvh::fuzz
