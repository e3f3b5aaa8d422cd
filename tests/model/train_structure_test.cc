// The structural assembly of a gear train (model/train_structure.h): the schema-1 identity, the
// torsional content of tier 1, the mirror image of a mesh whose first gear turns about -z, and the
// free rotations found from the meshes.
#include "gearnvh/model/train_structure.h"

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/modal_analysis.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

using testing::StandardPair;

double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

GearboxSpec FlexiblePair() {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  return testing::OnElasticShaftsWithInertias(spec);
}

GearboxSpec HelicalRigidPair(Hand pinion_hand) {
  GearboxSpec spec = StandardPair(23, 61, 2.5e-3, 20e-3);
  spec.pinion.helix_angle = spec.wheel.helix_angle = 20.0 * std::numbers::pi / 180.0;
  spec.pinion.hand = pinion_hand;
  spec.wheel.hand = pinion_hand == Hand::kRight ? Hand::kLeft : Hand::kRight;
  return spec;
}

TEST_CASE("a schema-1 gearbox assembled as a train equals its component model", "[train]") {
  for (const GearboxSpec& spec :
       {FlexiblePair(), HelicalRigidPair(Hand::kRight), HelicalRigidPair(Hand::kLeft)}) {
    CAPTURE(spec.pinion.helix_angle, spec.input_shaft.has_value());
    const ComponentModel pair = BuildComponentModel(spec);
    const TrainSpec train_spec = TrainOf(spec);
    const TrainStructure s = AssembleTrainStructure(train_spec, BuildGearTrain(train_spec));
    REQUIRE(s.dofs == pair.dofs);
    REQUIRE(s.meshes.size() == 1);
    // M, K, C come from the same element and body code in the same order: equal to the last bit
    // but for the order of summation (1e-14). G's wheel spin ratio is -z1/z2 from the topology
    // against -r_b1/r_b2 in the pair, equal to rounding (1e-14).
    CHECK(RelativeDifference(Eigen::MatrixXd(s.M), Eigen::MatrixXd(pair.M)) < 1e-14);
    CHECK(RelativeDifference(Eigen::MatrixXd(s.K), Eigen::MatrixXd(pair.K)) < 1e-14);
    CHECK(RelativeDifference(Eigen::MatrixXd(s.C), Eigen::MatrixXd(pair.C)) < 1e-14);
    CHECK(RelativeDifference(Eigen::MatrixXd(s.G), Eigen::MatrixXd(pair.G)) < 1e-14);
    // The mesh vectors from the same geometry and line-of-action code: equal to rounding.
    CHECK(RelativeDifference(s.meshes[0].v_drive, pair.v_drive) < 1e-14);
    CHECK(RelativeDifference(s.meshes[0].v_back, pair.v_back) < 1e-14);
    CHECK(RelativeDifference(s.meshes[0].friction_drive, pair.translation_friction_drive) < 1e-14);
    CHECK(s.free_rotations.cols() == 1);
    // The mesh damping from the gears' polar inertias (schema 1's m_e) on either side; the mean
    // stiffness at the train's static torque flow is the pair's to ~1e-12.
    CHECK(s.mesh_damping[0] == Approx(pair.mesh_damping).epsilon(1e-10));
  }
}

TEST_CASE("a rigid-shaft train's torsional part is the tier-1 model of TorsionalModes", "[train]") {
  const TrainSpec spec = testing::RigidTwoStage();
  ValidateTrainSpec(spec);
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure s = AssembleTrainStructure(spec, train);
  const TrainTorsionalModes t1 = TorsionalModes(train);
  // Body rotations R_j in th_z; tier 1 uses running angles theta_j = sign(w_j) th_z, so
  // R^T M R = M_1 and S R^T K_engaged R S = K_1 with S = diag(sign w_j). Same inertias and
  // stiffnesses summed in another order: 1e-13.
  const int n = static_cast<int>(train.topology.bodies.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int b = 0; b < n; ++b)
    S(b, b) = train.topology.bodies[static_cast<size_t>(b)].speed > 0 ? 1 : -1;
  const Eigen::MatrixXd R = s.body_rotations;
  const Eigen::MatrixXd M = R.transpose() * s.M * R;
  const Eigen::MatrixXd K = S * R.transpose() * Eigen::MatrixXd(s.EngagedStiffness()) * R * S;
  CHECK(RelativeDifference(M, t1.M) < 1e-13);
  CHECK(RelativeDifference(K, t1.K) < 1e-13);
  // The one free rotation found is the nominal motion: th_z,j proportional to w_j (signed).
  REQUIRE(s.free_rotations.cols() == 1);
  Eigen::VectorXd nominal(n);
  for (int b = 0; b < n; ++b) nominal[b] = train.topology.bodies[static_cast<size_t>(b)].speed;
  const Eigen::VectorXd found = R.transpose() * s.free_rotations.col(0);
  CHECK(std::abs(found.normalized().dot(nominal.normalized())) == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("a mesh whose first gear turns about -z is the mirror image of the +z mesh", "[train]") {
  // Mesh g3-g4 of the two-stage train: g3 on the layshaft turns against the input (sense -1).
  // Mirroring y -> -y maps (u_y, th_x, th_z) to their negatives and a right-hand gear to a left
  // one, so the local vectors equal the +z case's with those rows negated and the hands swapped.
  TrainSpec spec = testing::RigidTwoStage();
  const double beta = 12.0 * std::numbers::pi / 180.0;
  spec.gears[2].gear.helix_angle = spec.gears[3].gear.helix_angle = beta;
  spec.gears[2].gear.hand = Hand::kLeft;
  spec.gears[3].gear.hand = Hand::kRight;
  const TrainStructure s = AssembleTrainStructure(spec, BuildGearTrain(spec));
  REQUIRE(s.meshes[1].sense == -1.0);

  GearboxSpec mirror;  // the same pair driven about +z: pinion g3 right-hand
  mirror.name = "mirror";
  mirror.materials = spec.materials;
  mirror.pinion = spec.gears[2].gear;
  mirror.wheel = spec.gears[3].gear;
  mirror.pinion.hand = Hand::kRight;
  mirror.wheel.hand = Hand::kLeft;
  mirror.mesh = spec.meshes[1].mesh;
  mirror.operating.speed = 1.0;
  mirror.operating.torque = BuildGearTrain(spec).meshes[1].transmitted_torque;
  const ComponentModel plus = BuildComponentModel(mirror);
  const int na = s.gear_node[2], nb = s.gear_node[3];
  for (auto [train_v, pair_v] : {std::pair{&s.meshes[1].v_drive, &plus.v_drive},
                                 std::pair{&s.meshes[1].v_back, &plus.v_back}}) {
    for (int d = 0; d < 6; ++d) {
      const double flip = (d == kUy || d == kThx || d == kThz) ? -1.0 : 1.0;
      CAPTURE(d);
      // Same geometry, one sign per row: equal to rounding.
      CHECK((*train_v)[6 * na + d] ==
            Approx(flip * (*pair_v)[plus.PinionDof(NodeDof(d))]).margin(1e-15));
      CHECK((*train_v)[6 * nb + d] ==
            Approx(flip * (*pair_v)[plus.WheelDof(NodeDof(d))]).margin(1e-15));
    }
  }
}

TEST_CASE("the line-of-centres angles place the meshes: a turned layout has the same modes",
          "[train]") {
  // Rigid shafts on the isotropic default supports and isotropic loose-gear bearings: turning
  // every mesh by the same angle turns the whole model about z, so its frequencies do not change
  // (the dense eigensolver on two congruent pencils: 1e-7; the isotropic supports make close
  // lateral pairs, whose computed values move by ~1e-9 relative between the release and the
  // sanitizer builds' floating-point contraction). Turning one mesh only changes how the
  // meshes on the layshaft load it laterally, so the lateral frequencies move while the torsional
  // part (no lateral DOF) stays.
  TrainSpec spec = testing::RigidTwoStage();
  auto frequencies = [](const TrainSpec& s) {
    const TrainStructure st = AssembleTrainStructure(s, BuildGearTrain(s));
    return LowestNaturalModes(Eigen::MatrixXd(st.EngagedStiffness()), Eigen::MatrixXd(st.M), 12)
        .frequencies_hz;
  };
  const std::vector<double> base = frequencies(spec);
  TrainSpec turned = spec;
  for (TrainMesh& m : turned.meshes) m.center_line_angle = 0.7;
  const std::vector<double> all_turned = frequencies(turned);
  REQUIRE(all_turned.size() == base.size());
  for (size_t k = 0; k < base.size(); ++k) CHECK(all_turned[k] == Approx(base[k]).epsilon(1e-7));
  TrainSpec one = spec;
  one.meshes[1].center_line_angle = std::numbers::pi;  // g3-g4 on the other side of the layshaft
  const std::vector<double> moved = frequencies(one);
  double largest_change = 0.0;
  for (size_t k = 0; k < base.size(); ++k) {
    largest_change = std::max(largest_change, std::abs(moved[k] - base[k]) / base[k]);
  }
  CHECK(largest_change > 1e-3);
  const TrainStructure st = AssembleTrainStructure(one, BuildGearTrain(one));
  const TrainStructure st0 = AssembleTrainStructure(spec, BuildGearTrain(spec));
  for (size_t i = 0; i < st.meshes.size(); ++i) {
    CHECK(st.meshes[i].v_drive.dot(st.body_rotations.col(1)) ==
          Approx(st0.meshes[i].v_drive.dot(st0.body_rotations.col(1))).epsilon(1e-15));
  }
}

TEST_CASE("free rotations are found from the engaged meshes", "[train]") {
  const TrainSpec spec = testing::ElasticTwoStage();
  ValidateTrainSpec(spec);
  const TrainStructure s = AssembleTrainStructure(spec, BuildGearTrain(spec));
  CHECK(s.free_rotations.cols() == 1);
  // The elastic structure with every mesh at its mean stiffness has exactly that many zero modes
  // (an independent count: the scale-aware eigenvalue criterion of modal_analysis.h).
  const NaturalModes modes =
      LowestNaturalModes(Eigen::MatrixXd(s.EngagedStiffness()), Eigen::MatrixXd(s.M), 3);
  CHECK(modes.rigid_body_modes == 1);
  // The loose gear g5 in flight (mesh g6-g5 open) turns freely: two free rotations, one of them
  // g5's alone. The first stage open: the input and the rest turn independently.
  const Eigen::MatrixXd loose = FreeRotations(s, {true, true, false});
  CHECK(loose.cols() == 2);
  CHECK(FreeRotations(s, {false, true, true}).cols() == 2);
  CHECK(FreeRotations(s, {false, false, false}).cols() == 4);
  // The input torque balances every load by power, so the static load does no work on the free
  // rotation (the rigid-body mode carries no net mean torque): f^T R_free = 0 against the scale
  // of the input torque's own work (rounding, 1e-12).
  const double scale = s.static_force.cwiseAbs().maxCoeff() * s.free_rotations.col(0).norm();
  CHECK(std::abs(s.static_force.dot(s.free_rotations.col(0))) < 1e-12 * scale);
  // Every free rotation leaves every engaged mesh's approach at zero (to rounding of radii 1e-15).
  for (Eigen::Index c = 0; c < loose.cols(); ++c) {
    CHECK(std::abs(s.meshes[0].v_drive.dot(loose.col(c))) < 1e-15);
    CHECK(std::abs(s.meshes[1].v_drive.dot(loose.col(c))) < 1e-15);
  }
}

// The largest |eigenvalue| of the first-order system z' = [[0, I], [-M^-1 K, -M^-1 (C + w G)]] z
// of the structure with every mesh engaged at its mean stiffness, at the input speed w.
double LargestFirstOrderRate(const TrainStructure& s, double w) {
  const Eigen::MatrixXd M(s.M), K(s.EngagedStiffness()), C(s.C), G(s.G);
  const Eigen::Index n = M.rows();
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  REQUIRE(llt.info() == Eigen::Success);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -llt.solve(K);
  A.bottomRightCorner(n, n) = -llt.solve(C + w * G);
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(A, false);
  REQUIRE(eig.info() == Eigen::Success);
  return eig.eigenvalues().cwiseAbs().maxCoeff();
}

TEST_CASE("a rigid shaft's inertia is torsional: no gyroscopic moment and no tilt inertia",
          "[train]") {
  // The rigid input shaft of the elastic two-stage train with a lumped inertia of 8 and of 1000
  // kg m^2 (the vehicle reflected through a final drive is of that order). Taken as a disk's
  // polar inertia without a diametral one, it put w J on the tilts of the input node, whose only
  // tilt inertia is g1's I_d (~1e-4 kg m^2): a nutation at w (J + I_p)/I_d that grows in
  // proportion to J (~1e8 rad/s for 1000 kg m^2 at 1000 rpm, 125x that of 8 kg m^2).
  auto with_input_inertia = [](double j) {
    TrainSpec spec = testing::ElasticTwoStage(0.02);
    spec.shafts[0].inertia = j;
    ValidateTrainSpec(spec);
    return AssembleTrainStructure(spec, BuildGearTrain(spec));
  };
  const TrainStructure light = with_input_inertia(8.0), heavy = with_input_inertia(1000.0);
  const int node = light.gear_node[0];  // g1 sits on the input shaft's node
  // The inertia is on th_z alone: M differs in that one entry by 992 kg m^2 (to rounding of the
  // sum with g1's own I_p), G not at all.
  Eigen::MatrixXd dM = Eigen::MatrixXd(heavy.M) - Eigen::MatrixXd(light.M);
  const int thz = TrainStructure::Dof(node, kThz);
  CHECK(dM(thz, thz) == Approx(992.0).epsilon(1e-14));
  dM(thz, thz) = 0.0;
  CHECK(dM.isZero(0.0));
  CHECK(Eigen::MatrixXd(heavy.G - light.G).isZero(0.0));
  // The spectral radius of the first-order system does not grow with the inertia. A larger
  // inertia on th_z lowers every eigenvalue of the undamped problem (Rayleigh quotient), the
  // gyroscopic G does not involve th_z, and the largest |lambda| is a bearing or beam mode far
  // from the input's torsion: it stays put (factor 1.01, rounding and the coupled damping's
  // shift), where the defect scaled it by ~125.
  const double w = testing::ElasticTwoStage(0.02).operating.speed;
  const double r_light = LargestFirstOrderRate(light, w), r_heavy = LargestFirstOrderRate(heavy, w);
  INFO("largest |lambda|: " << r_light << " 1/s at 8 kg m^2, " << r_heavy << " at 1000");
  CHECK(r_heavy <= 1.01 * r_light);
}

}  // namespace
}  // namespace gearnvh
