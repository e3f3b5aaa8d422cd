// The modal tiers of a gear train (docs/gear-trains.md, "Tiers of a train"): the TrainStructure
// reduced to a few coordinates with every mesh's gap delta_i = v_i^T x kept exact.
//
//   tier 1  one torsional DOF per body (th_z at the body's first gear; Guyan: shafts rigid)
//   tier 2  tier 1 + u_x, u_y at every gear
//   tier 3  all six DOF at every gear (Guyan)
//   tier 4  tier 3 + the lowest 4 x (elastic shafts) Craig–Bampton fixed-interface modes of all
//           elastic shafts together
//   tier 5  tier 3 + the lowest 14 x (elastic shafts) fixed-interface modes
//   N20 simple  the lowest free-free modes of tier 5, as many as tier 4 has DOF
//   N20 MTA     N20 simple + the held and inertia-relief static shapes of every mesh and flank
//               as residual vectors (Dickens, Nakagawa & Wittbrodt 1997; docs/design.md §3)
// A cut never splits a cluster of equal eigenvalues, so these counts are minimums. Every mesh's
// gear DOF are interface DOF from tier 3 on, and each elastic shaft's interior is decoupled from
// the others once they are held, so its modes are computed shaft by shaft and then merged
// (LowestFixedInterfaceModes).
//
// Static compliance matrix at the meshes (the check quantity), with one rotation per body held (the
// pair's held gear rotations, made a matrix): G_ij = v_i^T x_j, K x_j = v_j subject to th_z = 0 at
// each body's first gear (a shaft's torsion between its gears stays in G). Holding them removes
// every body's free rotation with loads at the interface only, so Guyan and Craig–Bampton from tier
// 3 on reproduce G exactly (constraint modes are exact static shapes for interface loads). Modal
// truncation does not; with several meshes a series spring per mesh cannot restore a matrix, so MTA
// adds the residual vectors x_j - P P^T M x_j (P: kept modes), which put every x_j in the basis
// (beside the inertia-relief shapes, reduction/src/residual_vectors.h):
// the Galerkin solution of the held static problem is then x_j itself and G is exact again. The
// back flanks' shapes (v_back, another line of action) are added the same way.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh {

struct TrainReducedModel {
  Tier tier = Tier::kTier1;
  std::string name;
  int dof = 0;
  int boundary_dof = 0;        // physical gear DOF kept
  int modal_dof = 0;           // fixed-interface modes, truncated modes and residual vectors
  Eigen::MatrixXd M, C, K, G;  // G per unit input speed
  std::vector<Eigen::VectorXd> v_drive, v_back;  // per mesh, T^T v
  std::vector<Eigen::VectorXd> coupling_twist;   // per coupling, T^T w (TrainStructure's)
  Eigen::MatrixXd body_rotations;                // T^T R_j per body (columns)
  Eigen::VectorXd static_force;                  // T^T f
  Eigen::MatrixXd recovery;                      // T, full DOF x dof
  Eigen::MatrixXd static_compliance;             // G of this model, m/N (meshes x meshes)
  Eigen::MatrixXd full_static_compliance;        // G of the full FE model
  double compliance_error_vs_full = 0.0;         // ||G - G_full||_F / ||G_full||_F
  std::vector<double> natural_frequencies_hz;    // lowest 10, every mesh at its mean stiffness
  int rigid_body_modes = 0;                      // counted by the scale-aware criterion
};

// What the couplings' stages add to the reduced stiffness at their static twist: sum_j
// (k_static,j - k_1,j) w_j w_j^T (TrainStructure::coupling_static_increment; zero without stages).
Eigen::MatrixXd CouplingStaticStiffness(const TrainStructure& structure,
                                        const TrainReducedModel& reduced);

// Tiers 4, 5 and N20 need at least one elastic shaft.
bool TrainTierAvailable(const TrainStructure& structure, Tier tier);

// A bearing's point translations (x, y, z) per unit reduced coordinate: u + th x (d e_z) at its
// offset d from its node, as 3 rows of the recovery (the z row is zero where the tier has no axial
// DOF). Its force on the housing is diag(k_r, k_r, k_a) times these plus the damping's part.
Eigen::MatrixXd BearingPointRows(const StructureBearing& bearing, const TrainReducedModel& reduced);

// Throws TierNotAvailable when the tier is not available, and StructureNotReducible when the
// interior cannot be reduced (a direction no bearing holds).
TrainReducedModel ReduceTrain(const TrainStructure& structure, Tier tier,
                              const ReductionOptions& options = {});

// Several tiers at once, sharing the full model's compliance and the tier-5 basis (tier 5, N20
// simple and N20 MTA); the same results as ReduceTrain tier by tier.
std::vector<TrainReducedModel> ReduceTrainTiers(const TrainStructure& structure,
                                                const std::vector<Tier>& tiers,
                                                const ReductionOptions& options = {});

// The full FE model's static compliance matrix at the meshes (sparse LDL^T, gear rotations held).
Eigen::MatrixXd FullStaticComplianceMatrix(const TrainStructure& structure);

// Lowest `count` elastic natural frequencies of the full FE model with every mesh at its mean
// stiffness (dense up to `dense_limit` DOF, on the complement of the free rotations; sparse
// shift-invert Lanczos above, dropping the known number of free rotations), and the number of
// rigid-body modes.
// With `with_shapes`, their M-normalised shapes (physical DOF).
NaturalModes FullTrainModes(const TrainStructure& structure, int count, int dense_limit = 600,
                            bool with_shapes = false);

// The lowest `count` elastic modes of a reduced model with every mesh at its mean stiffness, its
// free rotations (the physical ones, M-orthogonally projected) removed by construction; with
// `with_shapes`, their M-normalised shapes in the reduced coordinates.
NaturalModes TrainReducedModes(const TrainStructure& structure, const TrainReducedModel& reduced,
                               int count, bool with_shapes = false);

}  // namespace gearnvh
