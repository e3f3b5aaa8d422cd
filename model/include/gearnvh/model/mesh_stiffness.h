// Deformation-compatible mesh stiffness over one mesh cycle (docs/design.md §2.3–2.4).
//
// Cycle fraction tau in [0, 1) = pinion angle / (2 pi / z1). Tooth pair j sits at roll position
//   s_j(tau) = s_start + (tau + j) p_b        (s measured along the line of action from T1)
// on the drive flank, and at C - s_j(tau) on the back flank (C = 2 (s_pitch + r_b1 theta_w): the
// two flanks of a tooth are mirror images, theta_w = pinion half-tooth angle at the working pitch
// circle). Every pair near the path has a pair stiffness k_j (series Hertz + both teeth, potential
// energy method) and an unloaded separation e_j >= 0 (linear tip relief inside the path; for a pair
// still outside the path, the tip relief continued plus the curvature gap (Δs)^2 / (2 rho) of the
// tip corner against the mating flank of radius of curvature rho). With transmitted load F = T /
// r_b2 all pairs share one approach delta:
//   sum_j k_j max(delta - e_j, 0) = F,
// solved exactly (sorted breakpoints). Outputs per tau: k(tau) = sum over loaded pairs of k_j,
// load-sharing ratios LSR_j = k_j (delta - e_j)_+ / F, loaded static transmission error
// LSTE(tau) = delta, and friction arms sigma = sum LSR_j sgn_j, a1 = sum LSR_j sgn_j rho1_j,
// a2 = sum LSR_j sgn_j rho2_j with rho1 = s_j, rho2 = |T1T2| - s_j, sgn_j = sign(s_j - s_pitch).
// At F = 0 the limit F -> 0+ is taken (pairs at the smallest separation share by stiffness).
// A stiffness override (rectangular / table / Fourier) replaces k(tau) by the user's data; the
// geometric pair positions still give the friction arms (sharing proportional to count).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct MeshStiffnessOptions {
  // Samples of the mesh cycle for the fine (reference) evaluation; >= 64.
  int samples_per_cycle = 2048;
  // Pairs farther than this many base pitches outside the path of contact are ignored; > 0.
  double path_extension_pitches = 0.5;
  // Face slices of a helical pair (the slice method, docs/gear-trains.md); >= 2. Each slice is a
  // spur pair of width b / N on the transverse section, displaced in mesh phase by its position
  // along the face times tan(beta_b) / p_bt.
  int helical_slices = 40;
  void Validate() const;
};

struct PairState {
  double roll = 0.0;        // s, m from T1 along the line of action (a helical pair's face edge)
  double stiffness = 0.0;   // k_j, N/m (a helical pair: its loaded slices)
  double separation = 0.0;  // e_j, m (a helical pair: its smallest)
  double load_share = 0.0;  // LSR_j
  int offset = 0;           // q: the pair entered the path of contact q mesh cycles ago
  bool loaded = false;
};

// One tooth pair on one face slice (the whole face for a spur pair).
struct ContactElement {
  double roll = 0.0, stiffness = 0.0, separation = 0.0, load_share = 0.0;
  int pair = 0;  // PairState::offset of its tooth pair
  bool loaded = false;
};

// One flank's state at one cycle fraction.
struct FlankSample {
  double stiffness = 0.0;  // sum of loaded pair stiffnesses, N/m
  double lste = 0.0;       // mesh approach delta at the operating load, m
  int loaded_pairs = 0;
  double friction_sigma = 0.0;       // sum LSR sgn
  double friction_arm_pinion = 0.0;  // a1, m
  double friction_arm_wheel = 0.0;   // a2, m
  static constexpr int kMaxPairs = 4;
  std::array<PairState, kMaxPairs> pairs{};
  int pair_count = 0;  // pairs considered (loaded or not)
};

struct MeshCycle {
  std::vector<double> tau;         // sample cycle fractions (midpoints of equal cells)
  std::vector<FlankSample> drive;  // drive flank samples
  std::vector<FlankSample> back;   // back flank samples
  double load = 0.0;               // F, N
  double back_phase = 0.0;         // C - 2 s_start, m (the back flank's mirrored offset)
  bool overridden = false;         // stiffness from user data
  std::vector<std::string> warnings;
};

struct MeshStiffnessSummary {
  double contact_ratio = 0.0;
  // Drive flank k(tau), N/m. `mean` is the cycle mean of the k the solver integrates,
  // sum_j k_j (tau_end - tau_begin)_j over the segmentation: exact for an override, 8-point
  // Gauss-Legendre between breaks otherwise. min and max come from the samples.
  double mean = 0.0, min = 0.0, max = 0.0;
  double single_pair_mean = 0.0;   // mean of k over samples with one loaded pair
  double double_pair_mean = 0.0;   // ... with two loaded pairs (0 if none)
  double lste_peak_to_peak = 0.0;  // m
  double load_sharing_max = 0.0;   // max LSR_j over the cycle
};

// Pair stiffness (series Hertz + pinion tooth + wheel tooth) at roll position s (clamped to the
// path).
class PairStiffness {
 public:
  // `tabulate`: evaluate through a cubic spline table (helical pairs) instead of the quadrature.
  PairStiffness(const MeshPair& pair, const PairGeometry& geometry, bool tabulate = false);
  double At(double roll) const;
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
  std::vector<std::string> warnings_;
};

enum class Flank { kDrive, kBack };

// Evaluates one flank's load sharing at any cycle fraction (the fine samples, segment quadrature
// and transition bisection all go through here).
class MeshEvaluator {
 public:
  MeshEvaluator(const MeshPair& pair, const PairGeometry& geometry,
                const MeshStiffnessOptions& options = {});
  FlankSample Evaluate(double tau, Flank flank) const;
  double load() const { return load_; }
  double back_phase() const { return back_phase_; }
  // Cycle fractions (in [0, 1)) where a pair crosses the pitch point on the given flank.
  double PitchCrossing(Flank flank) const;
  // Cycle fractions (in [0, 1)) where a stiffness override changes its law on the given flank:
  // the switches of a rectangular wave, the breakpoints of a table; none for Fourier data or the
  // potential energy method. The segmentation puts a boundary at each, so the override is
  // reproduced exactly (never averaged across a switch).
  std::vector<double> OverrideBreaks(Flank flank) const;
  bool overridden() const { return overridden_; }
  const PairGeometry& geometry() const { return g_; }
  const std::vector<std::string>& warnings() const { return pair_.warnings(); }

 private:
  StiffnessModel stiffness_;
  PairGeometry g_;
  PairStiffness pair_;
  int slices_ = 1;
  double reach_, load_, mirror_, back_phase_;
  bool overridden_;
  double relief_start_amount_ = 0, relief_start_length_ = 0, relief_end_amount_ = 0,
         relief_end_length_ = 0;
  double Separation(double s) const;
};

MeshCycle ComputeMeshCycle(const MeshPair& pair, const PairGeometry& geometry,
                           const MeshStiffnessOptions& options = {});

struct MeshSegmentation;
MeshStiffnessSummary SummarizeMeshCycle(const MeshCycle& cycle, const PairGeometry& geometry,
                                        const MeshSegmentation& segmentation);

// The stiffness an override gives at cycle fraction tau (drive flank), N/m.
double OverrideStiffness(const StiffnessModel& model, double tau);

}  // namespace gearnvh
