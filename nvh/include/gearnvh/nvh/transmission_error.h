// Dynamic transmission error statistics over whole mesh cycles (DESIGN.md §6).
//
// The trajectory is sampled at segment boundaries (unequal spacing), so the statistics are time
// integrals by the trapezoidal rule over [t_first, t_last], which spans whole mesh cycles:
//   mean = (1/T) ∫ delta dt,  RMS = sqrt((1/T) ∫ (delta - mean)^2 dt),  p-p = max - min of the
//   samples.
// The peak-to-peak of the sampled TE is a lower bound of the continuous one (samples every
// segment).
#pragma once

#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

struct TransmissionErrorStats {
  double mean = 0.0;                                   // m
  double rms = 0.0;                                    // m, about the mean
  double peak_to_peak = 0.0;                           // m
  double mesh_force_mean = 0.0, mesh_force_max = 0.0;  // N
  double dynamic_factor = 0.0;  // max mesh force / static mesh force (0 when unloaded)
  int samples = 0;
};

// `static_mesh_force` = T / r_b2 for the dynamic factor.
TransmissionErrorStats ComputeTransmissionErrorStats(const Trajectory& trajectory,
                                                     double static_mesh_force);

}  // namespace gearnvh
