// Resource and plausibility limits of a gearbox spec, checked before any work: each broken limit is
// an InputError naming the spec path, the value and the rule (with the model assumption it
// protects). Called by ValidateGearboxSpec, so every command applies them.
#pragma once

#include <cstddef>
#include <string>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"

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
  // N m s/rad: a viscous drag (operating.loads[i].viscous). Churning and bearing drag of large
  // industrial gears is of order 1-10 N m s/rad (1 % of 10 MW lost at 157 rad/s is 4 N m s/rad).
  static constexpr double kMaxViscousDrag = 1e3;
  // A coupling's torsional stiffness, N m/rad, and damping, N m s/rad. A clutch damper's first
  // stage is ~20 N m/rad, a car's halfshaft ~1e4, a truck's propshaft ~1e5, the flexible coupling
  // of a large industrial drive ~1e7; 1e8 is stiffer than any of them (a unit left out, 12000
  // N*m/deg read as rad, stays inside, so this bounds only the absurd). The damping likewise.
  static constexpr double kMaxCouplingStiffness = 1e8;
  static constexpr double kMaxCouplingDamping = 1e5;
  // rad: where a coupling's stage ends (couplings.NAME.stages[i].to). A clutch damper's stages end
  // within about +-25 deg, a dual-mass flywheel's arc springs within about +-70 deg; past 90 deg no
  // torsional spring works.
  static constexpr double kMaxCouplingStageAngle = 0.5 * 3.14159265358979323846;
  // A coupling's stages: clutch dampers have two to four, dual-mass flywheels two or three; each
  // stage after the first is a contact of the dynamics (key bits, roots, cycle-map rows).
  static constexpr int kMaxCouplingStages = 8;
  // m/s: the pitch-line velocity of every mesh. Above the fastest gears in service (high-speed
  // turbo gear units run at up to about 150-200 m/s, API 613); there centrifugal tooth loads,
  // windage and oil trapping, which the quasi-static mesh-stiffness model leaves out, dominate.
  static constexpr double kMaxPitchLineVelocity = 200.0;
  // Pa: gear and shaft materials, from gear plastics (POM, PA: about 1-3 GPa; 0.5 leaves room for
  // soft grades) to tungsten carbide (about 700 GPa). A unit left out (206 Pa for 206 GPa) gave a
  // mesh stiffness of 1 N/m and an LSTE of kilometres.
  static constexpr double kMinYoungsModulus = 0.5e9, kMaxYoungsModulus = 1.2e12;
  // kg/m^3: from gear plastics (about 900-1400) to the densest metals (osmium, 22,590).
  static constexpr double kMinDensity = 500.0, kMaxDensity = 25000.0;
  // Face width over (normal) module, b/m: thin stamped or fine-blanked gears (about 0.5-1) to
  // wide double-helical turbo, marine and mill gears (b/d up to 2-2.5 at 40-60 teeth: b/m up to
  // about 150). A unit left out is a factor of 1000 (face_width: 20 read as 20 m), far outside.
  static constexpr double kMinFaceWidthPerModule = 0.3, kMaxFaceWidthPerModule = 300.0;
  // Backlash over the tooth thickness at the pitch circle, s = pi m / 2: a quarter of it is far
  // beyond any gear's backlash (about 0.02-0.1 m) and leaves the teeth most of their thickness.
  static constexpr double kMaxBacklashPerToothThickness = 0.25;
  // A train's size: the meshes, gears and shafts a check builds and reduces (dense models of all
  // bodies) within minutes and a few hundred MB, and the meshes one gear takes part in (a planet
  // set has up to about 7; each mesh of a gear multiplies the contact states the solver tracks).
  static constexpr size_t kMaxTrainShafts = 64, kMaxTrainGears = 256, kMaxTrainMeshes = 128;
  static constexpr size_t kMaxMeshesPerGear = 12;
  // Two meshes between the same two shafts must have the same centre distance to within this
  // fraction of the smaller normal module: data rounded as drawings give it (shift coefficients to
  // 0.001, helix angles to 0.01 deg) moves it by a few micrometres, one tooth more or less by about
  // half a module.
  static constexpr double kCenterDistanceTolerancePerModule = 0.01;
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

// InputError at `path` (a gear's) unless its module is within [kMinModule, kMaxModule] and its
// face width within the b/m band: the gear's own scale, checked before any rule that compares it
// with the gear it meshes with (so that the implausible gear is the one named).
void RequireGearScale(const GearSpec& gear, const std::string& path);

// Tooth load per unit face width, N/m: the torque on gear `b` over its pitch radius and the
// narrower face, w = T_b / (r_b b_min). Limited to GearboxLimits::kMaxUnitLoad.
double ToothUnitLoad(const GearSpec& a, const GearSpec& b, double torque_on_b);

// InputError at `path` unless 0 <= inertia <= GearboxLimits::kMaxInertia (kg m^2, finite).
void RequireInertiaWithinLimit(const std::string& path, double inertia);

struct TrainSpec;
struct TrainTopology;

// An SI value shown in `unit` with 6 significant digits: "1500 rpm".
std::string InUnit(double value_si, const DisplayUnit& unit);

// Pitch radius of a gear, m: r = m_n z / (2 cos beta).
double PitchRadius(const GearSpec& gear);

// The pitch-line velocity rule: v = speed * velocity_per_speed <= kMaxPitchLineVelocity, where
// `velocity_per_speed` (m/s per rad/s of `speed`) is that of the fastest mesh, named `mesh`.
// InputError at `path` (the speed, written in `unit`) naming v, the limit and the largest speed
// allowed in `unit`.
void RequirePitchLineVelocity(const std::string& path, double speed, const DisplayUnit& unit,
                              double velocity_per_speed, const std::string& mesh);

// The mesh of a train with the highest pitch-line velocity per unit input speed (m/s per rad/s:
// |w_a / w_in| r_a over the meshes), and its name "meshes[i] (a-b)".
struct FastestMesh {
  double velocity_per_speed = 0.0;
  std::string name;
};
FastestMesh FastestPitchLine(const TrainSpec& spec, const TrainTopology& topology);

}  // namespace gearnvh
