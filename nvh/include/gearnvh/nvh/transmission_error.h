// Dynamic transmission error and mesh force statistics (docs/design.md §6, §10).
//
// Every statistic comes from the solver's exact statistics of the recorded window (closed-form
// integrals and in-segment extrema of the piecewise-exact solution, solver/exact_recorder.h):
//   mean = (1/T) int delta dt,  RMS = sqrt((1/T) int (delta - mean)^2 dt) (about the mean),
//   peak-to-peak = max delta - min delta over the window (extrema between segment boundaries
//   included), mesh force mean and maximum, dynamic factor = max force / static force.
// delta is the dynamic TE along the line of action, r_b1 th1 - r_b2 th2 (plus the lateral terms
// of the mesh vector in tiers 2+), measured from the nominal rigid rotation: in drive contact it
// includes half the backlash b (the gap closes at delta = b), so `mean` is b + the mean loaded
// deflection; `mean_from_contact` = mean - b is the mean measured from the drive-flank contact
// position.
#pragma once

#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

struct TransmissionErrorStats {
  double mean = 0.0;                                   // m
  double mean_from_contact = 0.0;                      // m, mean - half backlash
  double rms = 0.0;                                    // m, about the mean
  double peak_to_peak = 0.0;                           // m
  double max = 0.0, min = 0.0;                         // m
  double mesh_force_mean = 0.0, mesh_force_max = 0.0;  // N
  double dynamic_factor = 0.0;  // max mesh force / static mesh force (0 when unloaded)
  double duration = 0.0;        // s of recorded trajectory behind the statistics
};

// `static_mesh_force` = T / r_b2 for the dynamic factor; `half_backlash` b.
TransmissionErrorStats ComputeTransmissionErrorStats(const Trajectory& trajectory,
                                                     double static_mesh_force,
                                                     double half_backlash);

// Amplitude spectrum of the TE over the last `cycles` whole mesh cycles of the trajectory's
// uniform samples (`samples_per_cycle` per cycle; the record must end on a cycle boundary, as
// the solver's does). `analyzer` must have length cycles * samples_per_cycle (reuse one per length
// in a sweep). Throws std::out_of_range when the trajectory holds fewer samples.
AmplitudeSpectrum TeSpectrum(const Trajectory& trajectory, double mesh_period,
                             int samples_per_cycle, long cycles, SpectrumAnalyzer& analyzer);

}  // namespace gearnvh
