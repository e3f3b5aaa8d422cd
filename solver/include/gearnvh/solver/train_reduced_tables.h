// The train solver's tables on a reduced tier (tiers 2-5, N20 simple, N20 MTA) of a gear train
// (docs/gear-trains.md, "Simulating a train"; reduction/train_reduction.h).
//
// The reduced model (M, K_0, C_0, G, mesh vectors v_i and v_back,i, static force, recovery T) is
// taken to mass-normalised coordinates y = L^T x, M = L L^T (Cholesky), so that M = I and the
// tier-1 solver's diagonal-inertia code (generator, saltation, dense sub-step bound, projections)
// runs unchanged with inertia = 1:
//   K_y = L^-1 K_0 L^-T,  C_y = L^-1 (C_0 + w_in G) L^-T,  v_y = L^-1 v,  f_y = L^-1 T^T f,
//   d_y,k = B^T d_k   (engine order k's torque per unit amplitude on its shaft, as at tier 1, on
//   the shaft's reference node: B the bodies' angle rows below),
// and for every contact tuple K_s = K_y + sum_contact k v v^T, C_s = C_y + sum_contact c v v^T
// with the flank's vector (v for drive, v_back for back: from tier 2 on their lateral terms
// differ); with friction the force's direction is u = v +- mu w (train_tables.h), w_y = L^-1 T^T w
// from the flank's sliding translation (TrainMeshVectors::friction_drive/back) and the arms on
// s_a th_z of both gears, and the input gets tier 1's friction loss dT as a torque at its first
// gear. The gyroscopic terms are those of the pair's reduced tiers (C_0 + Omega G). Per mesh
// the segmentation, stiffness, errors, damping c_i and periods are tier 1's (BuildTrainTables).
// Body angles (the loose gears' rattle index): body b's angle in its own direction is
// s_b th_z at its first gear, the row s_b T(th_z, :) L^-T on y. The free rotation with every mesh
// engaged (TrainStructure::free_rotations, one for a connected train) is x_r = M^-1 T^T M_full R
// (the M-orthogonal projection; exact, constraint modes carry rigid rotations), y_r = L^T x_r
// normalised; the solver recentres it as at tier 1.
#pragma once

#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

// Tables of `reduced` (any tier of ReduceTrain on `structure`, which AssembleTrainStructure built
// from `spec` and `train`). Throws InputError (TrainReducedModel) when M is not positive definite
// or the train has not exactly one free rotation.
TrainTables BuildReducedTrainTables(const TrainSpec& spec, const GearTrain& train,
                                    const TrainStructure& structure,
                                    const TrainReducedModel& reduced,
                                    const TrainTableOptions& options = {});

// The tables of `tier`: tier 1 by BuildTrainTables (one torsional DOF per body, the bodies' own
// polar inertias), any other by AssembleTrainStructure, ReduceTrain and BuildReducedTrainTables.
// Throws TierNotAvailable when the tier is not available (TrainTierAvailable).
TrainTables BuildTrainTablesAtTier(const TrainSpec& spec, const GearTrain& train, Tier tier,
                                   const TrainTableOptions& options = {});

}  // namespace gearnvh
