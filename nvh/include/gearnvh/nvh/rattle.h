// Rattle indices of a recorded run (docs/design.md §6). Over N recorded mesh cycles of period T_m:
//   impacts per mesh cycle          n_d = drive impacts / N,  n_b = back impacts / N
//   impacts per excitation cycle    n * T_e / T_m, T_e = 2 pi / (order_1 Omega1) (first engine
//   order;
//                                   z1 / order mesh cycles); 0 without excitation
//   impact velocity RMS             sqrt(mean over impacts of g'^2), g' the gap rate at impact, m/s
//   impact energy per cycle         sum over impacts of (1/2) m_e g'^2 / N, J (m_e = J1 J2 /
//                                   (J1 r_b2^2 + J2 r_b1^2), the mesh's effective mass)
//   per recorded second             the impacts per flank, and the impact energy (W): the same
//                                   numbers a train reports per loose gear (train_statistics.h)
//   impact velocity max             max over impacts of |g'|, m/s
//   separation fraction             time in free flight / recorded time (exact, from event times)
//   wheel acceleration RMS          sqrt((1/T) ∫ (a - mean a)^2 dt) of the loose gear's (wheel's)
//                                   angular acceleration, exact (closed-form integrals over the
//                                   piecewise-exact solution, solver/exact_recorder.h)
//   acceleration ratio              that RMS divided by the same quantity for the same gearbox with
//                                   the backlash removed (a second run; 0 when not supplied)
//   regime                          kNoImpact | kSingleSided (drive impacts only) |
//                                   kDoubleSided (both flanks); kChaotic needs the Lyapunov
//                                   exponent and is not assigned here (RattleRegimeName: the
//                                   names "no impact", "single-sided", ... that results show).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

// The rattle regime of a mesh, shared by the pair and the train: from its impacts (ImpactRegime),
// replaced by kChaotic when the largest Lyapunov exponent says so (IsChaotic; atlases only).
enum class RattleRegime { kNoImpact, kSingleSided, kDoubleSided, kChaotic };
// "no impact" | "single-sided" | "double-sided" | "chaotic": the one name of each regime in
// results (JSON, CSV, text, HTML).
const char* RattleRegimeName(RattleRegime regime);
// The regime whose RattleRegimeName is `name` (reading results back), or nullopt.
std::optional<RattleRegime> RattleRegimeFromName(std::string_view name);
// kNoImpact without impacts, kSingleSided with drive-flank impacts only, else kDoubleSided.
RattleRegime ImpactRegime(long drive_impacts, long back_impacts);
// Chaotic: lambda T_f above `threshold` (per forcing cycle) and lambda above three standard errors.
bool IsChaotic(double per_forcing_cycle, double exponent_per_s, double standard_error_per_s,
               double threshold);

struct RattleIndices {
  double drive_impacts_per_cycle = 0.0, back_impacts_per_cycle = 0.0;
  double drive_impacts_per_excitation = 0.0, back_impacts_per_excitation = 0.0;
  double drive_impacts_per_second = 0.0, back_impacts_per_second = 0.0;
  double impact_velocity_rms = 0.0, impact_velocity_max = 0.0;  // m/s
  double impact_energy_per_cycle = 0.0;                         // J
  double impact_energy_per_second = 0.0;                        // W
  double separation_fraction = 0.0;
  double wheel_acceleration_rms = 0.0;  // rad/s^2
  double no_backlash_acceleration_rms = 0.0;
  double acceleration_ratio = 0.0;
  RattleRegime regime = RattleRegime::kNoImpact;
};

// `mesh_cycles_per_excitation` = z1 / order (0 without excitation); `no_backlash` may be null.
RattleIndices ComputeRattleIndices(const SolverResult& run, double effective_mass,
                                   double mesh_cycles_per_excitation,
                                   const SolverResult* no_backlash);

// RMS about the mean of the wheel's angular acceleration over the recorded window (exact).
double WheelAccelerationRms(const Trajectory& trajectory);

}  // namespace gearnvh
