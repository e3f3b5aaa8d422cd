// Resource and plausibility limits of a gearbox spec, checked before any work: each broken limit is
// an InputError naming the spec path, the value and the rule (with the model assumption it
// protects). Called by ValidateGearboxSpec, so every command applies them.
#pragma once

#include <string>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

// Documented limits (docs/input.md, "Limits").
struct GearboxLimits {
  static constexpr double kMinModule = 0.05e-3, kMaxModule = 100e-3;  // m
  static constexpr double kMinTipThickness = 0.2;  // times the module: pointed teeth below
  static constexpr double kMaxUnitLoad = 2e7;      // N/m (20 N/um) of face width
  static constexpr double kMaxSimulatedSeconds = 3600.0;
  static constexpr long kMaxRecordedCycles = 1000000;  // 32 samples each
  static constexpr double kMaxModalBytes = 2e9;        // dense modal analysis of the full FE model
  // kg m^2: any body's polar or diametral inertia. Above the largest rotating machines (a 15 MW
  // wind-turbine rotor is about 3e8 kg m^2); 1e300 overflowed the modal analysis to NaN.
  static constexpr double kMaxInertia = 1e9;
};

// Which limits apply. A schema-1 gearbox owns its operating point (kChecked). A train's mesh
// gearbox (MeshGearbox) takes its speed, load and excitation from the train, whose rules are stated
// on the train's input shaft and loads (ValidateTrainSpec), so there they are left to the train.
enum class OperatingLimits {
  kChecked,         // tooth load, excitation fluctuation and run length of spec.operating
  kLeftToTheTrain,  // only the gear, FE-size and recorded-cycle limits
};

void ValidateGearboxLimits(const GearboxSpec& spec,
                           OperatingLimits operating = OperatingLimits::kChecked);

// Tooth load per unit face width, N/m: the torque on gear `b` over its pitch radius and the
// narrower face, w = T_b / (r_b b_min). Limited to GearboxLimits::kMaxUnitLoad.
double ToothUnitLoad(const GearSpec& a, const GearSpec& b, double torque_on_b);

// InputError at `path` unless 0 <= inertia <= GearboxLimits::kMaxInertia (kg m^2, finite).
void RequireInertiaWithinLimit(const std::string& path, double inertia);

}  // namespace gearnvh
