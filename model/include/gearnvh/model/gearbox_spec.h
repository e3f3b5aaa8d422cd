// GearboxSpec: the validated, SI-unit description of one gearbox (schema gearnvh/1).
//
// Produced by the application's YAML loader (app/config), consumed by every stage below it.
// All quantities are SI: m, rad, kg, s, N, Pa. Angles are radians; speeds are rad/s.
// The loader guarantees the invariants stated next to each field; code that builds a spec by
// hand (tests, sweeps) should call ValidateGearboxSpec() before using it.
// The in-class initialisers are the schema defaults: the loader falls back to them, so each default
// is stated once, here.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace gearnvh {

struct Material {
  double youngs_modulus = 0.0;  // Pa, > 0
  double poisson_ratio = 0.0;   // -, in (-1, 0.5)
  double density = 0.0;         // kg/m^3, > 0

  bool operator==(const Material&) const = default;
};

struct TipRelief {
  double amount = 0.0;  // m, >= 0: profile removed at the tip
  double length = 0.0;  // m, >= 0: roll length along the line of action over which it grows

  bool operator==(const TipRelief&) const = default;
};

// Radial runout (eccentricity) of a gear, as the once-per-revolution transmission error it adds
// along the line of action: amplitude * sin(gear angle + phase), the gear angle counted in the
// gear's own direction of rotation from its position at t = 0.
struct Runout {
  double amplitude = 0.0;  // m, >= 0
  double phase = 0.0;      // rad

  bool operator==(const Runout&) const = default;
};

// Lead (helix) modifications of a gear's flanks: material removed across the face, measured
// normal to the flank along the line of action (y from the face's start, the end at smaller z).
struct LeadModification {
  double crowning = 0.0;           // m, >= 0: C (2 y / b - 1)^2, C at both face ends
  double end_relief_amount = 0.0;  // m, >= 0: removed at each face end ...
  double end_relief_length = 0.0;  // m, in (0, b / 2] when amount > 0: ... tapering to 0 over it
  double slope = 0.0;              // m, signed: helix slope deviation, slope * y / b (drive flank)

  bool operator==(const LeadModification&) const = default;
};

enum class Hand { kRight, kLeft };

struct GearSpec {
  int teeth = 0;        // >= 6
  double module = 0.0;  // m, > 0 (normal module for a helical gear)
  double pressure_angle = 20.0 * 3.141592653589793 / 180.0;  // rad, in (0, pi/4) (normal)
  double face_width = 0.0;                                   // m, > 0
  double bore_diameter = 0.0;                                // m, >= 0 and < root diameter
  std::string material;                                      // a key of GearboxSpec::materials
  double addendum_coefficient = 1.0;                         // h_a*, > 0
  double dedendum_coefficient = 1.25;  // h_f* = h_a* + c*, > addendum coefficient
  double profile_shift = 0.0;          // x, dimensionless
  std::optional<double> inertia;       // kg m^2 polar inertia override (default: solid disk)
  std::optional<double> mass;          // kg override (default: solid disk)
  std::optional<TipRelief> tip_relief;
  std::optional<LeadModification> lead;
  double helix_angle = 0.0;  // rad, in [0, pi/4): 0 for a spur gear
  Hand hand = Hand::kRight;  // of the helix; meaningful when helix_angle > 0
  std::optional<Runout> runout;
  // Cumulative pitch deviation of each tooth along the line of action, m; empty or one per tooth,
  // teeth numbered in the order they enter the mesh (tooth 0 is in the pair that enters the path
  // of contact at t = 0).
  std::vector<double> pitch_errors;

  bool operator==(const GearSpec&) const = default;
};

struct RectangularStiffness {
  double single = 0.0;         // N/m, > 0: one pair in contact
  double double_pair = 0.0;    // N/m, > 0: two pairs in contact
  double contact_ratio = 0.0;  // in (1, 2)

  bool operator==(const RectangularStiffness&) const = default;
};
struct TableStiffness {
  std::vector<double> phase;      // fraction of the mesh cycle, strictly increasing in [0, 1)
  std::vector<double> stiffness;  // N/m, > 0, same length as phase

  bool operator==(const TableStiffness&) const = default;
};
struct FourierStiffness {
  double mean = 0.0;                     // N/m, > 0
  std::vector<double> cos_coefficients;  // N/m, harmonics 1..n of the mesh frequency
  std::vector<double> sin_coefficients;  // N/m

  bool operator==(const FourierStiffness&) const = default;
};
struct PotentialEnergyStiffness {
  bool operator==(const PotentialEnergyStiffness&) const = default;
};

using StiffnessModel =
    std::variant<PotentialEnergyStiffness, RectangularStiffness, TableStiffness, FourierStiffness>;

struct StaticTransmissionError {
  std::vector<double> amplitudes;  // m, harmonics 1..n of the mesh frequency
  std::vector<double> phases;      // rad, same length

  bool operator==(const StaticTransmissionError&) const = default;
};

struct MeshSpec {
  double backlash = 0.0;                  // m, > 0: total clearance along the line of action (= 2b)
  double damping_ratio = 0.05;            // in [0, 1)
  double friction_coefficient = 0.0;      // in [0, 0.5]
  std::optional<double> center_distance;  // m; default: standard centre distance
  StiffnessModel stiffness = PotentialEnergyStiffness{};
  StaticTransmissionError static_transmission_error;
  // Manufacturing mesh misalignment f_ma (ISO 6336-1), m, signed: the drive flanks' separation at
  // the face's end (larger z) exceeds that at its start by this much, growing linearly across it.
  double misalignment = 0.0;

  bool operator==(const MeshSpec&) const = default;
};

struct ShaftSegment {
  double length = 0.0;          // m, > 0
  double outer_diameter = 0.0;  // m, > 0
  double inner_diameter = 0.0;  // m, in [0, outer)

  bool operator==(const ShaftSegment&) const = default;
};

struct BearingSpec {
  double at = 0.0;                // m, position from the shaft's left end, within the shaft
  double radial_stiffness = 0.0;  // N/m, >= 0
  double axial_stiffness = 0.0;   // N/m, >= 0
  double tilt_stiffness = 0.0;    // N m/rad, >= 0
  double damping = 0.0;           // N s/m, >= 0 (radial and axial)

  bool operator==(const BearingSpec&) const = default;
};

struct LumpedInertia {
  double at = 0.0;         // m, within the shaft
  double polar = 0.0;      // kg m^2, >= 0
  double diametral = 0.0;  // kg m^2, >= 0
  double mass = 0.0;       // kg, >= 0 (schema 2; schema 1 lumps no mass)

  bool operator==(const LumpedInertia&) const = default;
};

struct ShaftSpec {
  std::string material;
  std::vector<ShaftSegment> segments;  // from the left end, in order; at least one
  double gear_at = 0.0;                // m, within the shaft
  std::vector<BearingSpec> bearings;   // at least one
  std::vector<LumpedInertia> inertias;
  std::optional<double> element_length;  // m, > 0; default chosen from geometry

  double Length() const {
    double total = 0.0;
    for (const auto& s : segments) total += s.length;
    return total;
  }

  bool operator==(const ShaftSpec&) const = default;
};

// What an engine order prescribes on its shaft s (docs/gearbox-yaml.md and docs/gear-trains.md,
// `kind`).
enum class ExcitationKind {
  kAcceleration,  // the torque J_s a sin(k W_s t + phi): a per unit of the shaft's own inertia
  kTorque,        // the torque T sin(k W_s t + phi)
};

struct ExcitationOrder {
  double order = 0.0;      // > 0, multiple of the speed of the shaft it acts on
  double amplitude = 0.0;  // >= 0: rad/s^2 (kAcceleration) or N m (kTorque)
  double phase = 0.0;      // rad
  ExcitationKind kind = ExcitationKind::kAcceleration;
  // The shaft it acts on, in its direction of rotation (a train's shaft name); empty: the input
  // shaft (schema 1: the pinion's).
  std::string on{};

  bool operator==(const ExcitationOrder&) const = default;
};

// The gear `OperatingSpec::torque` acts on: a load resisting the wheel, or the torque the pinion
// transmits (converted to the wheel by the tooth ratio, so the mesh carries the same force).
enum class TorqueOn { kWheel, kPinion };

// A unit a quantity is shown in: shown value = SI value * per_si.
struct DisplayUnit {
  std::string symbol;
  double per_si = 1.0;

  bool operator==(const DisplayUnit&) const = default;
};

struct OperatingSpec {
  double speed = 0.0;   // rad/s, > 0: mean pinion speed
  double torque = 0.0;  // N m, >= 0: mean torque on the gear `torque_on` names
  TorqueOn torque_on = TorqueOn::kWheel;
  // The units the input wrote speed and torque in (SI for plain numbers), for output in them.
  DisplayUnit speed_unit{"rad/s", 1.0};
  DisplayUnit torque_unit{"N m", 1.0};
  std::vector<ExcitationOrder> excitation;

  bool operator==(const OperatingSpec&) const = default;
};

// Modal tier names as in docs/design.md §3.
enum class Tier { kTier1, kTier2, kTier3, kTier4, kTier5, kN20Simple, kN20Mta };
// Every tier, in the order `check`, `tiers` and reports list them.
inline constexpr std::array<Tier, 7> kAllTiers{Tier::kTier1, Tier::kTier2, Tier::kTier3,
                                               Tier::kTier4, Tier::kTier5, Tier::kN20Simple,
                                               Tier::kN20Mta};

// How the points of a range are spaced: evenly (linear) or geometrically (log; from > 0).
enum class AxisScale { kLinear, kLog };

struct SweepRange {
  double from = 0.0;  // SI value of the parameter
  double to = 0.0;
  int points = 0;  // >= 2
  AxisScale scale = AxisScale::kLinear;

  // Point i of 0 .. points-1: from + (to - from) i / (points - 1), or from (to / from)^(i /
  // (points - 1)) on a log scale (consecutive points in the ratio (to / from)^(1 / (points - 1))).
  // The ends are from and to exactly.
  double Point(int i) const {
    if (points <= 1 || i <= 0) return from;
    if (i >= points - 1) return to;
    const double t = static_cast<double>(i) / (points - 1);
    return scale == AxisScale::kLog ? from * std::pow(to / from, t) : from + (to - from) * t;
  }

  bool operator==(const SweepRange&) const = default;
};

struct AtlasAxis {
  std::string parameter;  // dotted schema path, e.g. "operating.speed"
  SweepRange range;

  bool operator==(const AtlasAxis&) const = default;
};

struct AnalysisSpec {
  Tier tier = Tier::kTier1;
  int segments_per_cycle = 32;  // >= 4
  int cycles = 2000;            // >= 1
  int transient_cycles = 500;   // >= 0
  SweepRange speed_sweep{500.0 * 2.0 * 3.141592653589793 / 60.0,
                         6000.0 * 2.0 * 3.141592653589793 / 60.0, 56};
  std::optional<AtlasAxis> atlas_x;
  std::optional<AtlasAxis> atlas_y;

  bool operator==(const AnalysisSpec&) const = default;
};

struct GearboxSpec {
  std::string name;
  std::map<std::string, Material> materials;
  GearSpec pinion;
  GearSpec wheel;
  MeshSpec mesh;
  std::optional<ShaftSpec> input_shaft;   // carries the pinion
  std::optional<ShaftSpec> output_shaft;  // carries the wheel
  OperatingSpec operating;
  AnalysisSpec analysis;

  const Material& MaterialOf(const GearSpec& gear) const { return materials.at(gear.material); }

  // The mean torque T2 resisting the wheel, N m: `operating.torque` itself, or a pinion torque T1
  // times r_b2 / r_b1 = z2 / z1 (both gears share module and pressure angle), so the static mesh
  // force T1 / r_b1 = T2 / r_b2 is the same either way.
  double WheelTorque() const {
    return operating.torque_on == TorqueOn::kWheel
               ? operating.torque
               : operating.torque * static_cast<double>(wheel.teeth) / pinion.teeth;
  }

  bool operator==(const GearboxSpec&) const = default;
};

// "wheel" or "pinion".
const char* TorqueOnName(TorqueOn on);

// Human-readable tier name ("tier 1" … "tier 5", "N20 simple", "N20 MTA").
const char* TierName(Tier tier);

}  // namespace gearnvh
