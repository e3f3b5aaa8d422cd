#include "gearnvh/nvh/rattle.h"

#include <algorithm>
#include <cmath>

namespace gearnvh {

const char* RattleRegimeName(RattleRegime regime) {
  switch (regime) {
    case RattleRegime::kNoImpact:
      return "no impact";
    case RattleRegime::kSingleSided:
      return "single-sided";
    case RattleRegime::kDoubleSided:
      return "double-sided";
    case RattleRegime::kChaotic:
      return "chaotic";
  }
  return "?";
}

std::optional<RattleRegime> RattleRegimeFromName(std::string_view name) {
  for (RattleRegime r : {RattleRegime::kNoImpact, RattleRegime::kSingleSided,
                         RattleRegime::kDoubleSided, RattleRegime::kChaotic}) {
    if (name == RattleRegimeName(r)) return r;
  }
  return std::nullopt;
}

RattleRegime ImpactRegime(long drive_impacts, long back_impacts) {
  if (drive_impacts + back_impacts == 0) return RattleRegime::kNoImpact;
  return back_impacts == 0 ? RattleRegime::kSingleSided : RattleRegime::kDoubleSided;
}

bool IsChaotic(double per_forcing_cycle, double exponent_per_s, double standard_error_per_s,
               double threshold) {
  return per_forcing_cycle > threshold && exponent_per_s > 3.0 * standard_error_per_s;
}

double WheelAccelerationRms(const Trajectory& t) {
  const TrajectoryStatistics& st = t.statistics;
  return st.wheel_acceleration.Rms(st.duration);
}

RattleIndices ComputeRattleIndices(const SolverResult& run, double effective_mass,
                                   double mesh_cycles_per_excitation,
                                   const SolverResult* no_backlash) {
  RattleIndices r;
  const SolverSummary& s = run.summary;
  const double recorded_cycles = static_cast<double>(std::max<long>(1, s.recorded_cycles));
  r.drive_impacts_per_cycle = static_cast<double>(s.drive_impacts) / recorded_cycles;
  r.back_impacts_per_cycle = static_cast<double>(s.back_impacts) / recorded_cycles;
  r.drive_impacts_per_excitation = r.drive_impacts_per_cycle * mesh_cycles_per_excitation;
  r.back_impacts_per_excitation = r.back_impacts_per_cycle * mesh_cycles_per_excitation;
  double square = 0.0;
  int impacts = 0;
  for (const EventRecord& e : run.trajectory.events) {
    if (e.from != ContactState::kFree) continue;  // impacts: free -> contact
    square += e.gap_rate * e.gap_rate;
    r.impact_velocity_max = std::max(r.impact_velocity_max, std::abs(e.gap_rate));
    ++impacts;
  }
  r.impact_velocity_rms = impacts > 0 ? std::sqrt(square / impacts) : 0.0;
  r.impact_energy_per_cycle = 0.5 * effective_mass * square / recorded_cycles;
  if (s.recorded_s > 0.0) {
    r.drive_impacts_per_second = static_cast<double>(s.drive_impacts) / s.recorded_s;
    r.back_impacts_per_second = static_cast<double>(s.back_impacts) / s.recorded_s;
    r.impact_energy_per_second = 0.5 * effective_mass * square / s.recorded_s;
  }
  r.separation_fraction = s.recorded_s > 0.0 ? s.separated_s / s.recorded_s : 0.0;
  r.wheel_acceleration_rms = WheelAccelerationRms(run.trajectory);
  if (no_backlash) {
    r.no_backlash_acceleration_rms = WheelAccelerationRms(no_backlash->trajectory);
    r.acceleration_ratio = r.no_backlash_acceleration_rms > 0.0
                               ? r.wheel_acceleration_rms / r.no_backlash_acceleration_rms
                               : 0.0;
  }
  r.regime = ImpactRegime(s.drive_impacts, s.back_impacts);
  return r;
}

}  // namespace gearnvh
