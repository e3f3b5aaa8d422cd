// Campbell data of a gear train (docs/gear-trains.md, "Campbell diagram of a train"): the modes of
// a train tier followed over the input speed (ComputeCampbell of campbell.h), against the order
// lines of every shaft (order 1: f = |w_j| / 2 pi) and of every mesh (harmonics h = 1..3 of its
// mesh frequency: f = h z_a |w_a| / 2 pi), all proportional to the input speed, with the critical
// input speeds where a line crosses a tracked mode.
#pragma once

#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/nvh/campbell.h"
#include "gearnvh/reduction/train_reduction.h"

namespace gearnvh {

// The order lines, in multiples of the input speed: "<shaft> 1x" per shaft, then "mesh <name> hx"
// for h = 1..3 per mesh.
std::vector<OrderLine> TrainOrderLines(const TrainSpec& spec, const GearTrain& train);

// The tier linearised with every mesh in drive contact at its mean stiffness and mesh damping,
// with the physical model's energy classes and every gear as a disk (spin sense of its body).
LinearRotorModel LinearisedTrain(const TrainStructure& structure, const TrainReducedModel& reduced,
                                 const GearTrain& train);

// Campbell data over the input speeds (rad/s, ascending).
CampbellData TrainCampbell(const TrainSpec& spec, const GearTrain& train,
                           const TrainStructure& structure, const TrainReducedModel& reduced,
                           const std::vector<double>& input_speeds, const CampbellOptions& options);

}  // namespace gearnvh
