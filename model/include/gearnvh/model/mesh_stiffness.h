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
// Misalignment and lead modifications (docs/design.md §2.5): with a static load F > 0, the face is
// cut into strips (the helical slices; a spur face alike) and each strip's separation grows
// linearly across it by the face mismatch m(y) (misalignment, crowning, end relief, helix slope),
// so a strip carries k (delta - e)_+ integrated over its width: the sharing above becomes a
// piecewise-quadratic equation in delta, solved exactly, and k(tau) is the tangent stiffness
// dF/d delta. The face load factor K_Hbeta is the peak of the cycle-mean line load over F / b.
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
  // Face slices of a helical pair (the slice method, docs/gear-trains.md) and of a loaded spur pair
  // whose face is misaligned or lead-modified; >= 2. Each slice is a spur pair of width b / N on
  // the transverse section, displaced in mesh phase by its position along the face times
  // tan(beta_b) / p_bt (0 for spur).
  int face_slices = 40;
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

// One tooth pair on one face slice (the whole face for an aligned spur pair): a strip of the face
// whose separation grows linearly across it from `separation` at one edge by `spread` at the other
// (0: uniform), with its stiffness spread evenly over its width.
struct ContactElement {
  double roll = 0.0, stiffness = 0.0, separation = 0.0, load_share = 0.0;
  double spread = 0.0;           // m, >= 0
  bool grows_toward_end = true;  // the separation grows toward the slice's larger face position
  double tangent = 0.0;          // d(its load) / d delta at the solution, N/m (<= stiffness)
  int slice = 0;                 // face slice, from the face's start (smaller z)
  int pair = 0;                  // PairState::offset of its tooth pair
  bool loaded = false;
};

// Solves sum_j F_j(delta) = load exactly over the contact elements, F_j the load of element j at
// approach delta: k (delta - e)_+ for a uniform element, k / s * integral over [e, e + s] of
// (delta - u)_+ du for one of spread s (piecewise quadratic in delta). Returns delta and sets each
// element's load share, tangent stiffness and `loaded`. At load 0 the elements at the smallest
// separation share by stiffness (the limit load -> 0+ of uniform elements).
double ShareLoad(std::vector<ContactElement>& elements, double load);

// The load per unit face width at each slice edge (N / slices + 1 positions from the face start):
// the sum over the elements of their line load there; an inner edge takes the larger of its two
// slices' values (helical slices' pairs differ across an edge). `face_width` b, m.
std::vector<double> LineLoadAtSliceEdges(const std::vector<ContactElement>& elements, double delta,
                                         int slices, double face_width);

// The load across the drive flank's face under the static load (docs/design.md §2.5). The
// misalignment components are set for every mesh; the distribution only where the face is
// modelled (MeshEvaluator::face_modelled), else positions are empty and the load is uniform.
struct FaceLoad {
  // The linear mismatch across the common face, m, signed as MeshSpec::misalignment: f_ma, the
  // shafts' static deflection f_sh, the two gears' lead slopes over the common face (a gear's
  // slope times b / b_gear), and their sum F_beta_y.
  double manufacturing_misalignment = 0.0, shaft_misalignment = 0.0, lead_slopes = 0.0;
  double linear_mismatch = 0.0;
  double face_width = 0.0;        // b, m: the common face
  std::vector<double> position;   // m from the face start (smaller z), the slice edges
  std::vector<double> line_load;  // N/m, the mesh-cycle mean at each position
  std::vector<double> mismatch;   // m, the separation the misalignment and leads add there
  double factor = 1.0;            // K_Hbeta: the largest line_load over F / b
  double loaded_width = 0.0;      // m, the narrowest loaded width over the cycle (b if uniform)
  // ISO 6336-1 method C's K_Hbeta at |F_beta_y| (no running-in allowance, no crowning) with
  // c_gamma_beta = 0.85 times the full face's mean stiffness per unit width: 1 + x up to 2, then
  // 2 sqrt(x), x = |F_beta_y| c_gamma_beta / (2 F / b), F the force along the line of action.
  // ISO's formula at the model's F_beta_y, not a method C rating (no F_beta_x factors or floor).
  double iso_method_c = 1.0;
  // Whether the face is modelled strip by strip, and why not where it is misaligned or modified:
  // no static load, or a stiffness override (warned), or a mismatch that cancels (uniform).
  enum class Model { kUniform, kModelled, kUnloaded, kOverridden };
  Model model = Model::kUniform;
  double full_face_stiffness = 0.0;  // N/m, cycle mean with the mismatch removed (kModelled)
  bool modelled() const { return model == Model::kModelled; }
  // Whether anything misaligns or modifies the face (else the load is uniform by construction).
  bool misaligned() const {
    return model != Model::kUniform || manufacturing_misalignment != 0.0 ||
           shaft_misalignment != 0.0 || lead_slopes != 0.0;
  }
};

// One flank's state at one cycle fraction.
struct FlankSample {
  double stiffness = 0.0;  // sum of loaded pair (tangent) stiffnesses, N/m
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
  // The drive flank's load across the face; empty positions when the face is aligned and
  // unmodified or unloaded (then the load is uniform: K_Hbeta = 1).
  FaceLoad face;
  double load = 0.0;        // F, N
  double back_phase = 0.0;  // C - 2 s_start, m (the back flank's mirrored offset)
  bool overridden = false;  // stiffness from user data
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
  double face_load_factor = 1.0;   // K_Hbeta (MeshCycle::face)
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

// The load across the face at one cycle fraction.
struct FaceSample {
  std::vector<double> line_load;     // N/m at the slice edges (LineLoadAtSliceEdges)
  double loaded_width = 0.0;         // m: the width of the face that carries load
  double full_face_stiffness = 0.0;  // N/m: the mesh stiffness with the mismatch removed
};

// Evaluates one flank's load sharing at any cycle fraction (the fine samples, segment quadrature
// and transition bisection all go through here).
class MeshEvaluator {
 public:
  MeshEvaluator(const MeshPair& pair, const PairGeometry& geometry,
                const MeshStiffnessOptions& options = {});
  // With `face` (where the face is modelled): the same state's load across the face as well.
  FlankSample Evaluate(double tau, Flank flank, FaceSample* face = nullptr) const;
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
  // Whether the face is modelled strip by strip: the static load is > 0, no stiffness override,
  // and some misalignment or lead modification gives the face a mismatch.
  bool face_modelled() const { return face_; }
  // The drive flank's mismatch at the slice edges, m (its smallest value 0); empty if uniform.
  const std::vector<double>& face_mismatch() const { return drive_mismatch_; }
  int slices() const { return slices_; }

 private:
  StiffnessModel stiffness_;
  PairGeometry g_;
  PairStiffness pair_;
  int slices_ = 1;
  double face_width_ = 0.0;
  double mismatch_scale_ = 0.0;  // the largest mismatch, m
  bool face_ = false;
  // The separation misalignment and leads add at the slice edges (drive: all of them; back: the
  // symmetric leads, crowning and end relief), m; empty when uniform.
  std::vector<double> drive_mismatch_, back_mismatch_;
  std::vector<ContactElement> Elements(double tau, Flank flank) const;
  void FaceAt(const std::vector<ContactElement>& elements, double delta, FaceSample& face) const;
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
