#include "gearnvh/solver/train_reduced_tables.h"

#include <algorithm>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

TrainTables BuildReducedTrainTables(const TrainSpec& spec, const GearTrain& train,
                                    const TrainStructure& structure,
                                    const TrainReducedModel& reduced,
                                    const TrainTableOptions& options) {
  // Per mesh segmentation, periods, damping and the common period are tier 1's.
  TrainTables t = BuildTrainTables(spec, train, options);
  const TrainTopology& topo = train.topology;
  const int n = reduced.dof;
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (reduced.M + reduced.M.transpose()));
  if (llt.info() != Eigen::Success) {
    throw InputError("TrainReducedModel.M", 0, reduced.name, "must be positive definite");
  }
  // One free rotation turns the train; each fixed shaft adds its own, which nothing moves.
  const auto fixed_shafts = std::count_if(spec.shafts.begin(), spec.shafts.end(),
                                          [](const TrainShaft& s) { return s.fixed; });
  if (structure.free_rotations.cols() != 1 + fixed_shafts) {
    throw InputError("TrainStructure.free_rotations", 0,
                     std::to_string(structure.free_rotations.cols()),
                     "must be 1 plus one per fixed shaft (a connected train with every mesh "
                     "engaged)");
  }
  const Eigen::MatrixXd L = llt.matrixL();
  // L^-1 X for a matrix or vector X.
  const auto left = [&](const Eigen::MatrixXd& X) -> Eigen::MatrixXd {
    return L.triangularView<Eigen::Lower>().solve(X);
  };
  const auto congruent = [&](const Eigen::MatrixXd& X) -> Eigen::MatrixXd {
    return left(left(X).transpose()).transpose();  // L^-1 X L^-T
  };
  const Eigen::MatrixXd& T = reduced.recovery;
  const auto sense = [&](int body) {
    return topo.bodies[static_cast<size_t>(body)].speed > 0.0 ? 1.0 : -1.0;
  };
  const auto first_thz = [&](int body) {
    return TrainStructure::Dof(structure.body_node[static_cast<size_t>(body)], kThz);
  };

  t.tier = reduced.tier;
  t.n = n;
  AssignErrorInputs(t);  // m = 2n + 1 + 2K + error inputs at this tier's n
  t.inertia = Eigen::VectorXd::Ones(n);
  t.structural_stiffness = congruent(reduced.K);
  t.structural_damping = congruent(reduced.C + t.input_speed * reduced.G);
  // The structure's static force holds the input torque without the friction loss (tier 1's dT).
  t.force = left(reduced.static_force + t.friction_loss_torque * sense(topo.input_body) *
                                            T.row(first_thz(topo.input_body)).transpose());
  const int bodies = t.bodies();
  Eigen::MatrixXd angles(n, bodies);  // columns: s_b T(th_z, :)^T
  for (int b = 0; b < bodies; ++b) angles.col(b) = sense(b) * T.row(first_thz(b)).transpose();
  t.body_angles = left(angles).transpose();
  // Each order's torque on the bodies' angles (tier 1's directions), as generalised forces B^T d.
  t.excitation_directions = t.body_angles.transpose() * t.excitation_directions;
  for (TrainMeshTable& mt : t.meshes) {  // the couplings' stages: their twist's row
    if (mt.gear_mesh()) continue;
    mt.v = sense(mt.body_a) * left(reduced.coupling_twist[static_cast<size_t>(mt.coupling)]);
    mt.v_back = mt.v;
    mt.FindSupport();
  }
  for (size_t i = 0; i < static_cast<size_t>(t.gear_meshes); ++i) {
    TrainMeshTable& mt = t.meshes[i];
    mt.v = left(reduced.v_drive[i]);
    mt.v_back = left(reduced.v_back[i]);
    mt.distinct_back = mt.v_back != mt.v;
    mt.FindSupport();
    // Friction: the flanks' sliding translations and the arms on s_a th_z of both gears
    // (train_structure.h), in these coordinates.
    const TrainMeshVectors& vectors = structure.meshes[i];
    const auto arm = [&](int gear) -> Eigen::VectorXd {
      const int dof = TrainStructure::Dof(structure.gear_node[static_cast<size_t>(gear)], kThz);
      return left(vectors.sense * T.row(dof).transpose());
    };
    SetFrictionForces(mt, {left(T.transpose() * vectors.friction_drive),
                           left(T.transpose() * vectors.friction_back), arm(train.meshes[i].gear_a),
                           arm(train.meshes[i].gear_b)});
  }
  // The train's free rotation R (every body at its nominal speed: th_z = w_b on its nodes; a fixed
  // shaft's stays out): x_r = M^-1 T^T M_full R, y_r = L^T x_r, unit length (M-normalised).
  Eigen::VectorXd speeds(static_cast<Eigen::Index>(topo.bodies.size()));
  for (size_t b = 0; b < topo.bodies.size(); ++b)
    speeds[static_cast<Eigen::Index>(b)] = topo.bodies[b].speed;
  const Eigen::VectorXd mr = structure.M * (structure.body_rotations * speeds);
  const Eigen::VectorXd x_r = llt.solve(T.transpose() * mr);
  Eigen::VectorXd y_r = L.transpose() * x_r;
  y_r.normalize();
  t.rigid_rotation = y_r;
  t.recenter_row = y_r.transpose();
  // Each fixed shaft's rotation the same way, made orthogonal to r and to the ones before.
  t.standing_rotations = Eigen::MatrixXd::Zero(n, 0);
  for (size_t b = 0; b < topo.bodies.size(); ++b) {
    if (topo.bodies[b].speed != 0.0) continue;
    const Eigen::VectorXd mb =
        structure.M * structure.body_rotations.col(static_cast<Eigen::Index>(b));
    Eigen::VectorXd y = L.transpose() * llt.solve(T.transpose() * mb);
    y -= y_r.dot(y) * y_r;
    for (Eigen::Index c = 0; c < t.standing_rotations.cols(); ++c) {
      y -= t.standing_rotations.col(c).dot(y) * t.standing_rotations.col(c);
    }
    t.standing_rotations.conservativeResize(n, t.standing_rotations.cols() + 1);
    t.standing_rotations.rightCols(1) = y.normalized();
  }
  t.bearings = structure.bearings;
  t.bearing_force_rows =
      Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(t.bearings.size()), t.m);
  for (size_t b = 0; b < t.bearings.size(); ++b) {
    const StructureBearing& sb = t.bearings[b];
    const Eigen::MatrixXd point = left(BearingPointRows(sb, reduced).transpose()).transpose();
    const Eigen::Vector3d k(sb.radial_stiffness, sb.radial_stiffness, sb.axial_stiffness);
    auto rows = t.bearing_force_rows.middleRows(3 * static_cast<Eigen::Index>(b), 3);
    rows.leftCols(n) = k.asDiagonal() * point;
    rows.middleCols(n, n) = sb.damping * point;
  }
  return t;
}

TrainTables BuildTrainTablesAtTier(const TrainSpec& spec, const GearTrain& train, Tier tier,
                                   const TrainTableOptions& options) {
  if (tier == Tier::kTier1) return BuildTrainTables(spec, train, options);
  ThrowIfCancelled(options.cancel);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  ThrowIfCancelled(options.cancel);
  const TrainReducedModel reduced = ReduceTrain(structure, tier);
  return BuildReducedTrainTables(spec, train, structure, reduced, options);
}

}  // namespace gearnvh
