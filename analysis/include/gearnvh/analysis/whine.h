// Whine in the frequency domain (`gearnvh whine`, docs/cli.md; the model: docs/design.md §14): the
// steady-state response of any gearbox (a pair is the train TrainOf(spec)) at any tier, every mesh
// at its mean stiffness on its loaded flank, to its harmonic inputs over the speeds of
// analysis.speed_sweep (harmonic_response.h). The inputs, each exact as a Fourier coefficient:
//   - each mesh's loaded static transmission error as the solver integrates it (per segment the
//     static solution of k_j (delta - e_j) = F: the LSTE and the user's STE at their segment
//     means), at mesh orders k;
//   - runout a sin(w_g t + phi) of a gear at 1x its shaft's order;
//   - pitch errors (piecewise constant over a revolution of the gear, the solver's pair weights) at
//     every multiple n of the gear's shaft order;
//   - the excitation orders as torques T sin(k W_s t + phi) on their shafts s (T = J_s a for an
//     acceleration order), at order k W_s / W of the input.
// Line orders are multiples of the input shaft's speed W. The lines solved are the mesh orders
// 1..mesh_harmonics of every mesh, the orders +-1..sideband_orders of each gear with pitch errors
// around them (and below the first: 1..sideband_orders), 1x each gear with runout, and the
// excitation orders; lines at one order from several sources are one line (superposed).
// Contact loss is not modelled: a mesh is flagged at a speed where the sum of its dynamic force
// amplitudes over the lines reaches its static force (the force could then reach zero, and the
// time-domain solver is the answer there).
#pragma once

#include <array>
#include <atomic>
#include <complex>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/option_names.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh {

// A transfer from the bearing forces to one response point of the housing, as an FE model or a
// hammer test gives it: per bearing and direction the complex acceleration at the point per unit
// force on the housing, (m/s^2)/N, over frequency (interpolated linearly in its real and imaginary
// parts; a line outside a curve's range has no response).
struct HousingCurve {
  std::string shaft;                 // the bearing's shaft
  int bearing = -1;                  // its index in the shaft's bearings; -1: the default support
  int direction = 0;                 // 0 x, 1 y, 2 z
  std::vector<double> frequency_hz;  // strictly ascending, >= 0
  std::vector<std::complex<double>> transfer;  // (m/s^2)/N
  int line = 0;                                // where the curve starts in its table (messages)
};
struct HousingTransfer {
  std::string source;  // the table's file (messages)
  std::vector<HousingCurve> curves;
};

struct WhineOptions {
  Tier tier = Tier::kTier1;
  int speeds = 2000;        // speeds over analysis.speed_sweep's range and scale, 2..100000
  int mesh_harmonics = 3;   // mesh orders 1..mesh_harmonics of every mesh, 1..20
  int sideband_orders = 2;  // pitch-error lines +-1..sideband_orders shaft orders, 0..10
  int threads = 1;          // 0: all hardware threads
  // Cancellation: once set, RunWhine throws Cancelled. Not owned; may be null.
  const std::atomic<bool>* cancel = nullptr;
  // The response at one point of the housing, summed over the bearings with phase (none: the
  // bearing forces are the result). Its bearings must exist at the tier (not at tier 1).
  std::optional<HousingTransfer> housing;
  OptionNames names;  // how the caller names speeds, harmonics, sidebands and jobs
  // Throws InputError naming the option (names) and its rule.
  void Validate() const;
};

// What a line's first source is (its label names every source).
enum class WhineLineKind { kMeshOrder, kSideband, kShaftOrder, kExcitation };

struct WhineLine {
  double order = 0.0;  // multiples of the input shaft's speed
  WhineLineKind kind = WhineLineKind::kMeshOrder;
  std::string label;  // "1x mesh g1-g2", "1x mesh g1-g2 - 1x g1", "1x g1", "excitation 2x"
};

struct WhineMesh {
  std::string name;
  double mean_stiffness = 0.0;  // N/m, of the loaded flank
  double static_force = 0.0;    // N along the line of action
  bool back_flank_loaded = false;
  // [line][speed]: amplitudes of the dynamic TE (the approach along the drive flank's line of
  // action, as the time-domain solver's TE, m) and of the mesh force (N).
  std::vector<std::vector<double>> te_amplitude_m, force_amplitude_n;
  // [speed]: the sum of the force amplitudes over the lines, N, and whether it reaches the static
  // force (the force can then reach zero: contact may be lost).
  std::vector<double> force_amplitude_sum_n;
  std::vector<bool> contact_loss;
};

struct WhineBearing {
  std::string shaft;  // the shaft it holds
  int index = -1;     // in the shaft's bearings; -1: the default support of a rigid shaft
  double at = 0.0;    // m along the shaft
  // [line][direction x, y, z][speed]: the amplitude of its force on the housing, N.
  std::vector<std::array<std::vector<double>, 3>> force_amplitude_n;
};

struct WhineBody {
  std::string name;
  std::vector<std::vector<double>> speed_amplitude_rad_s;  // [line][speed]
};

// A natural mode of the mean model (every mesh at its mean stiffness; undamped, at rest: no
// gyroscopic terms), with the share of its modal strain energy phi^T K phi in each mesh
// (k_i (v_i^T phi)^2) and each bearing (its springs times its point's motion squared).
struct WhineMode {
  double frequency_hz = 0.0;
  std::vector<double> mesh_energy;     // per mesh, fraction of the mode's strain energy
  std::vector<double> bearing_energy;  // per bearing (WhineResult::bearings)
  double MeshEnergy() const;           // the meshes' sum
};

// A critical speed: a line's frequency meets a mode's inside the speed range.
struct WhineCriticalSpeed {
  double speed_rad_s = 0.0;
  size_t line = 0;  // in WhineResult::lines
  size_t mode = 0;  // in WhineResult::modes
};

// The housing's response: [line][speed] the amplitude of the acceleration at the point, m/s^2,
// NaN where the line's frequency lies outside some curve's range.
struct WhineHousing {
  std::string source;
  std::vector<std::vector<double>> acceleration_m_s2;
};

struct WhineResult {
  Tier tier = Tier::kTier1;
  int dof = 0;
  std::vector<double> speed_rad_s;  // of the input shaft, ascending as analysis.speed_sweep
  AxisScale speed_scale = AxisScale::kLinear;
  std::vector<WhineLine> lines;  // ascending order
  std::vector<WhineMesh> meshes;
  std::vector<WhineBearing> bearings;  // empty at tier 1 (no lateral DOF)
  std::vector<WhineBody> bodies;
  std::optional<WhineHousing> housing;
  // The modes up to 1.25 times the highest line frequency in the range, ascending, and the
  // critical speeds ranked by their mode's mesh strain energy (the whine-relevant first).
  std::vector<WhineMode> modes;
  std::vector<WhineCriticalSpeed> critical_speeds;
  std::vector<std::string> warnings;
  // Speeds at which some mesh may lose contact.
  int ContactLossSpeeds() const;
};

using WhineProgress = std::function<void(int done, int total)>;

// Throws InputError for a tier the gearbox does not have, Cancelled when cancelled.
WhineResult RunWhine(const TrainSpec& spec, const WhineOptions& options,
                     const WhineProgress& progress = {});

}  // namespace gearnvh
