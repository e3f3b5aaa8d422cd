// ReducedModel: a component model reduced to one of the modal tiers of docs/design.md §3, ready for
// the exact solver — dense M, C, K, G, gap and friction vectors and forcing in reduced coordinates,
// and the recovery matrix back to the physical DOF (q_full = T x).
//
// Tiers (boundary = gear-node DOF kept physically, so delta = v^T x stays exact):
//   tier 1   2 DOF  pinion and wheel torsion (Guyan: the shafts rotate rigidly)
//   tier 2   6 DOF  per gear torsion + u_x + u_y (Guyan onto the bearing/shaft stiffness)
//   tier 3  12 DOF  per gear all 6 DOF (Guyan)
//   tier 4  20 DOF  tier 3 + 8 Craig–Bampton fixed-interface modes
//   tier 5  40 DOF  tier 3 + 28 fixed-interface modes ("N40 full")
//   N20 simple  20  lowest 20 free-free modes of tier 5 (2 rigid rotations + 18 elastic)
// A cut never splits a cluster of equal eigenvalues (an axisymmetric shaft's x and y bending): the
// count grows to the cluster's end (reduction/src/mode_cut.h), e.g. 41 DOF at tier 5 of
// examples/flexible_shafts.yaml, whose 28th and 29th fixed-interface modes are one pair.
//   N20 MTA     23  N20 simple + each flank's held and inertia-relief static shapes as Ritz vectors
//                   (modal truncation augmentation, vector form: Dickens et al. 1997; Rixen 2001):
//                   two held shapes and one relief direction. The one form for every gearbox: on a
//                   train it restores the whole compliance matrix, the meshes' coupling too, and
//                   brings the frequencies to tier 5's (docs/design.md §3).
//
// Static mesh compliance (the check quantity): the compliance along the drive line of action at the
// mesh with both gear bodies' rotations held, g = v^T q where K q = v subject to th_z(pinion) =
// th_z(wheel) = 0. Holding the gear rotations removes the structure's free torsional rotations with
// boundary loads only, so Guyan and Craig–Bampton reproduce it exactly (constraint modes are exact
// static shapes for boundary loads); modal truncation does not, and MTA's residual vectors make
// the static shapes themselves part of the basis, so g is exact again.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"

namespace gearnvh {

// How many of the lowest natural frequencies a reduced model (pair or train) reports.
inline constexpr int kReportedFrequencies = 10;

struct ReductionOptions {
  // Modal damping ratio of the Craig–Bampton fixed-interface modes (shaft structural damping), [0,
  // 1).
  double structural_damping_ratio = 0.01;
  // Interior problems smaller than this use a dense eigensolver (Spectra needs ncv < n); >= 8.
  int dense_eigen_threshold = 64;
  void Validate() const;
};

struct ReducedModel {
  Tier tier = Tier::kTier1;
  std::string name;
  int dof = 0;
  int boundary_dof = 0;        // physical gear-node DOF kept
  int modal_dof = 0;           // Craig–Bampton or truncated modal coordinates
  Eigen::MatrixXd M, C, K, G;  // G per unit pinion speed (force Omega1 G x')
  Eigen::VectorXd v_drive, v_back;
  Eigen::VectorXd friction_translation_drive, friction_translation_back;
  Eigen::VectorXd pinion_torsion, wheel_torsion;  // T^T e_thz of each gear
  Eigen::VectorXd static_force;                   // T^T f
  Eigen::MatrixXd recovery;                       // T, full DOF x dof
  double static_mesh_compliance = 0.0;            // g of this model, m/N
  double full_static_mesh_compliance = 0.0;       // g of the full FE model, m/N
  double compliance_error_vs_full = 0.0;          // (g - g_full) / g_full
  std::vector<double> natural_frequencies_hz;     // lowest 10 at the mean mesh stiffness
  int rigid_body_modes = 0;
  double wall_seconds = 0.0;

  Eigen::VectorXd FrictionVector(Flank flank, double sigma, double arm_pinion,
                                 double arm_wheel) const {
    return sigma *
               (flank == Flank::kDrive ? friction_translation_drive : friction_translation_back) +
           arm_pinion * pinion_torsion + arm_wheel * wheel_torsion;
  }
};

// True when the component model can be reduced to `tier` (tiers 4, 5 and N20 need shaft interiors).
bool TierAvailable(const ComponentModel& model, Tier tier);

// A tier the model cannot be reduced to. An InputError at the library's own name "tier" (the
// argument), the tier's name and the rule; the app names where the user chose the tier
// (analysis.tier, the Python keyword tier).
class TierNotAvailable : public InputError {
 public:
  TierNotAvailable(Tier tier, std::string requirement)
      : InputError("tier", 0, TierName(tier), std::move(requirement)), tier_(tier) {}
  Tier tier() const { return tier_; }

 private:
  Tier tier_;
};

// A structure whose interior cannot be reduced or solved statically (a direction no bearing
// holds). An InputError at the library's name "structure"; the app names the shafts: of the file.
class StructureNotReducible : public InputError {
 public:
  explicit StructureNotReducible(std::string reason)
      : InputError("structure", 0, "", std::move(reason)) {}
};

// Throws TierNotAvailable when the tier is not available: the one rule `check` and the solver
// commands share.
void RequireTierAvailable(const ComponentModel& model, Tier tier);

// Reduces the model. Throws TierNotAvailable when the tier is not available and
// StructureNotReducible when the interior cannot be reduced.
ReducedModel ReduceModel(const ComponentModel& model, Tier tier,
                         const ReductionOptions& options = {});

// Static mesh compliance of the full FE model (sparse, gear rotations held), m/N.
double FullStaticMeshCompliance(const ComponentModel& model);

// Lowest natural frequencies of a reduced model of `model` linearised at mean drive contact, and
// the number of rigid-body modes: the criterion of model/modal_analysis.h on the shapes recovered
// to the full model (ReducedStrainMagnitude), so every tier counts what the full model counts.
std::vector<double> ReducedNaturalFrequencies(const ComponentModel& model, const ReducedModel& r,
                                              double mean_mesh_stiffness, int count,
                                              int* rigid_body_modes = nullptr);

// The full model's strain magnitude (FullStrainMagnitude) of a reduced shape, recovered (T x), at
// the mean mesh stiffness.
StrainMagnitude ReducedStrainMagnitude(const ComponentModel& model, const ReducedModel& r,
                                       double mean_mesh_stiffness);

}  // namespace gearnvh
