// Dynamic transmission error statistics over whole mesh cycles (DESIGN.md §6).
//
// The trajectory is sampled at segment boundaries (unequal spacing), so the statistics are time
// integrals by the trapezoidal rule over [t_first, t_last], which spans whole mesh cycles:
//   mean = (1/T) ∫ delta dt,  RMS = sqrt((1/T) ∫ (delta - mean)^2 dt),  p-p = max - min of the
//   samples.
// The peak-to-peak of the sampled TE is a lower bound of the continuous one (samples every
// segment).
#pragma once

#include "gearnvh/nvh/spectrum.h"
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

// `count` uniform samples of the TE from `start` at `rate_hz`, by cubic Hermite interpolation
// between the trajectory's samples (values and rates at segment boundaries, so the error is
// O(h^4) in the sample spacing: 3e-4 relative at the third mesh harmonic with 32 segments, where
// linear interpolation would lose 3 %). Times outside the samples' span throw std::out_of_range.
std::vector<double> ResampleTe(const Trajectory& trajectory, double start, double rate_hz,
                               long count);

// Amplitude spectrum of the TE over the last `cycles` whole mesh cycles of the trajectory (which
// must end on a cycle boundary), resampled uniformly at samples_per_cycle per cycle (ResampleTe).
// `analyzer` must have length cycles * samples_per_cycle (reuse one per length in a sweep).
AmplitudeSpectrum TeSpectrum(const Trajectory& trajectory, double mesh_period,
                             int samples_per_cycle, long cycles, SpectrumAnalyzer& analyzer);

}  // namespace gearnvh
