// The time histories `simulate --out` writes: trajectory.csv (the uniform samples) and events.csv
// (the located contact changes), for a pair and for a gear train (docs/cli.md, "simulate").
#pragma once

#include <cstdio>
#include <string>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh::app {

// A pair: time_s, te_m, mesh_force_n, pinion_speed_rad_s, wheel_speed_rad_s, contact. Streamed:
// at the sample storage bound (4e6 samples) the text is ~0.4 GB.
void WriteTrajectoryCsv(const Trajectory& t, std::FILE* f);
// time_s, from, to, gap_rate_m_s.
std::string EventsCsv(const Trajectory& t);

// A train: time_s, then per mesh (file order) <mesh>.te_m, <mesh>.mesh_force_n, <mesh>.contact,
// then per bearing when the histories hold its force <bearing>.force_x_n, _y_n, _z_n (bearings
// named as BearingName), then per coupling (file order) <coupling>.twist_rad, <coupling>.torque_n_m
// (TrainCouplingResponse). Streamed.
void WriteTrainTrajectoryCsv(const TrainHistories& h, const TrainTables& tables,
                             const TrainSpec& spec, std::FILE* f);
// time_s, mesh, from, to, gap_rate_m_s.
std::string TrainEventsCsv(const TrainHistories& h, const TrainTables& tables);

}  // namespace gearnvh::app
