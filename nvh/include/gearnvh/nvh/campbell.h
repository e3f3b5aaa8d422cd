// Campbell data of a linearised rotor/gear model (docs/design.md §6).
//
// At pinion speed Omega the free vibration of M q'' + (C + Omega G) q' + K q = 0 has eigenvalues
// lambda = sigma + i omega of the first-order form [[0, I], [-M^-1 K, -M^-1 (C + Omega G)]].
// Damped natural frequencies f = omega / 2 pi (Im lambda > 0, |lambda| >= min_frequency_hz; rigid
// rotations excluded) and damping ratios zeta = -sigma / |lambda| are computed at every speed;
// every mode below max_frequency_hz at some speed is tracked (not a fixed count; at least the
// lowest mode, so a diagram whose modes all lie above the limit still shows the first), followed
// from speed to speed by the modal assurance criterion of the displacement part of the
// eigenvectors,
//   MAC(a, b) = |a^H b|^2 / ((a^H a)(b^H b)),
// with a greedy global assignment (the best remaining pair first), so two modes whose
// frequencies cross keep their identities (frequency sorting would swap them). Order lines are
// f = order * Omega / 2 pi; a critical speed is where a tracked mode and an order line cross
// (linear interpolation between neighbouring speeds).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh {

struct LinearRotorModel {
  Eigen::MatrixXd M, K, G;  // G per unit pinion speed (gyroscopic force Omega G q')
  Eigen::MatrixXd C;        // viscous damping; empty: undamped
  // Optional mode identification (see the header): the kinetic-energy matrices of the torsional,
  // lateral and axial coordinates in these coordinates, and each disk's lateral displacement rows
  // with its spin sense (+1 with the pinion, -1 against).
  std::array<Eigen::MatrixXd, 3> class_mass;
  struct Disk {
    Eigen::RowVectorXd ux, uy;
    double spin = 1.0;
  };
  std::vector<Disk> disks;
};

enum class ModeType { kTorsional, kLateral, kAxial, kCoupled, kUnknown };
enum class Whirl { kNone, kForward, kBackward };
const char* ModeTypeName(ModeType t);
const char* WhirlName(Whirl w);

struct ModeInfo {
  ModeType type = ModeType::kUnknown;
  Whirl whirl = Whirl::kNone;
  std::array<double, 3> energy_fraction{};  // torsional, lateral, axial
  // "torsional", "lateral, forward whirl", "coupled torsional-lateral", ...
  std::string Label() const;
};

struct OrderLine {
  std::string label;   // e.g. "1x mesh", "2x pinion", "1x wheel"
  double order = 0.0;  // multiples of the pinion speed
};

struct CampbellOptions {
  // Every mode below this frequency at some speed is tracked (callers pass 3x the highest mesh
  // frequency of the sweep); > 0.
  double max_frequency_hz = 1e4;
  double min_frequency_hz = 1.0;  // below this an eigenvalue is a rigid rotation; >= 0
  double class_threshold = 0.8;   // energy fraction that names a mode's type; in (0.5, 1]
  void Validate() const;
};

struct CriticalSpeed {
  std::string order;
  int mode = 0;  // index into CampbellData's modes (0-based)
  double speed_rad_s = 0.0, speed_rpm = 0.0, frequency_hz = 0.0;
};

struct CampbellData {
  std::vector<double> speeds_rad_s;
  // frequency_hz[mode][speed], the MAC of each match with the previous speed (1 at the first) and
  // the damping ratio; NaN where a mode is not found (above the tracked range).
  std::vector<std::vector<double>> frequency_hz, mac, damping_ratio;
  std::vector<ModeInfo> modes;  // per tracked mode
  std::vector<OrderLine> orders;
  std::vector<CriticalSpeed> critical_speeds;
};

// Mesh orders 1..3 (z1 per pinion revolution), shaft orders 1..2 of both shafts and the
// excitation orders (AddExcitationLines).
std::vector<OrderLine> GearOrderLines(int pinion_teeth, int wheel_teeth,
                                      const std::vector<ExcitationOrder>& excitation = {});

// Orders equal to rounding (within 1e-9 relative: speeds multiplied stage by stage differ in the
// last bit) are one line.
bool SameOrder(double a, double b);

// A line `label` at `order`, or, when a line of that order exists, its label joined to that
// line's ("mesh g1-g2 3x = mesh g3-g4 2x").
void AddOrderLine(std::vector<OrderLine>& lines, const std::string& label, double order);

// The engine or motor orders of the file's excitation as lines "excitation 2x" ("excitation 2x
// layshaft" for an order of another shaft), at `reference_orders[i]` (orders of the reference
// shaft, the pinion's or the input shaft's; empty: each order as written); one at the order of an
// existing line joins its label ("2x pinion = excitation 2x") instead.
void AddExcitationLines(std::vector<OrderLine>& lines,
                        const std::vector<ExcitationOrder>& excitation,
                        const std::vector<double>& reference_orders = {});

// The tier linearised in drive contact at the mean mesh stiffness, with the mesh
// damping, and the physical model's energy classes and disks for mode identification.
LinearRotorModel LinearisedRotor(const ComponentModel& model, const ReducedModel& reduced);

// Speeds in rad/s (ascending, > 0 recommended: at rest forward and backward whirl coincide).
CampbellData ComputeCampbell(const LinearRotorModel& model, const std::vector<double>& speeds,
                             const std::vector<OrderLine>& orders, const CampbellOptions& options);

}  // namespace gearnvh
