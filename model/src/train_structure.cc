#include "gearnvh/model/train_structure.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "gearnvh/model/input_error.h"
#include "structure_assembly.h"

namespace gearnvh {

void TrainStructureOptions::Validate() const {
  structure.Validate();
  auto positive = [](const char* name, double v) {
    if (!(v > 0.0)) {
      throw InputError(std::string("TrainStructureOptions.") + name, 0, std::to_string(v),
                       "must be > 0");
    }
  };
  positive("loose_radial_stiffness", loose_radial_stiffness);
  positive("loose_axial_stiffness", loose_axial_stiffness);
  positive("loose_tilt_stiffness", loose_tilt_stiffness);
  if (!(loose_damping >= 0.0)) {
    throw InputError("TrainStructureOptions.loose_damping", 0, std::to_string(loose_damping),
                     "must be >= 0");
  }
}

Eigen::SparseMatrix<double> TrainStructure::EngagedStiffness() const {
  Eigen::SparseMatrix<double> k = K;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const Eigen::SparseVector<double> v = meshes[i].v_drive.sparseView();
    k += mean_stiffness[i] * (v * v.transpose());
  }
  for (size_t j = 0; j < coupling_twist.size(); ++j) {
    if (coupling_static_increment[j] == 0.0) continue;
    const Eigen::SparseVector<double> w = coupling_twist[j].sparseView();
    k += coupling_static_increment[j] * (w * w.transpose());
  }
  return k;
}

Eigen::MatrixXd FreeRotations(const TrainStructure& s, const std::vector<bool>& engaged) {
  const Eigen::Index bodies = s.body_rotations.cols();
  const auto meshes = static_cast<Eigen::Index>(s.meshes.size());
  Eigen::MatrixXd B =
      Eigen::MatrixXd::Zero(meshes + static_cast<Eigen::Index>(s.coupled_bodies.size()), bodies);
  for (size_t i = 0; i < s.meshes.size(); ++i) {
    if (engaged[i]) {
      B.row(static_cast<Eigen::Index>(i)) = s.meshes[i].v_drive.transpose() * s.body_rotations;
    }
  }
  // Couplings, always engaged: their twist th_a - th_b, scaled like a mesh row (a base radius).
  const double radius = meshes > 0 ? B.topRows(meshes).cwiseAbs().maxCoeff() : 1.0;
  for (size_t j = 0; j < s.coupled_bodies.size(); ++j) {
    B(meshes + static_cast<Eigen::Index>(j), s.coupled_bodies[j].first) = radius;
    B(meshes + static_cast<Eigen::Index>(j), s.coupled_bodies[j].second) = -radius;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  Eigen::Index rank = 0;
  for (Eigen::Index i = 0; i < sv.size(); ++i) {
    if (sv[i] > 1e-9 * sv[0]) ++rank;
  }
  return s.body_rotations * svd.matrixV().rightCols(bodies - rank);
}

TrainStructure AssembleTrainStructure(const TrainSpec& spec, const GearTrain& train,
                                      const TrainStructureOptions& options) {
  options.Validate();
  const TrainTopology& topo = train.topology;
  const ComponentModelOptions& opt = options.structure;
  const double input_speed = topo.bodies[static_cast<size_t>(topo.input_body)].speed;
  auto spin = [&](int body) { return topo.bodies[static_cast<size_t>(body)].speed / input_speed; };

  TrainStructure s;
  detail::Assembler as;
  s.gear_node.assign(spec.gears.size(), -1);
  std::vector<double> gear_offset(spec.gears.size(), 0.0);  // from a rigid shaft's node
  std::vector<int> shaft_node(spec.shafts.size(), -1);      // rigid: its node; elastic: -1
  for (size_t si = 0; si < spec.shafts.size(); ++si) {
    const TrainShaft& shaft = spec.shafts[si];
    const int id = static_cast<int>(si);
    const double w = spin(id);  // shaft si is body si
    std::vector<int> fixed;
    std::vector<double> positions;
    for (size_t g = 0; g < spec.gears.size(); ++g) {
      if (spec.gears[g].shaft != shaft.name) continue;
      positions.push_back(spec.gears[g].at.value_or(0.0));
      if (spec.gears[g].mounting == Mounting::kFixed) fixed.push_back(static_cast<int>(g));
    }
    if (shaft.elastic) {
      s.elastic_shafts.push_back(id);
      detail::AddShaftElements(*shaft.elastic, spec.materials.at(shaft.elastic->material), id,
                               positions, w, opt.default_elements_per_shaft, s.nodes, as);
      for (int g : fixed) {
        const TrainGear& gear = spec.gears[static_cast<size_t>(g)];
        s.gear_node[static_cast<size_t>(g)] = detail::NearestNode(s.nodes, id, *gear.at);
        as.AddBody(s.gear_node[static_cast<size_t>(g)],
                   DiskBody(gear.gear, spec.materials.at(gear.gear.material)), w);
      }
      detail::AddShaftSupports(*shaft.elastic, id, w, s.nodes, as);
      for (size_t b = 0; b < shaft.elastic->bearings.size(); ++b) {
        const BearingSpec& bearing = shaft.elastic->bearings[b];
        s.bearings.push_back({id, static_cast<int>(b), bearing.at,
                              detail::NearestNode(s.nodes, id, bearing.at), 0.0,
                              bearing.radial_stiffness, bearing.axial_stiffness, bearing.damping,
                              bearing.tilt_stiffness});
      }
      continue;
    }
    const int node = static_cast<int>(s.nodes.size());
    shaft_node[si] = node;
    s.nodes.push_back({id, 0.0});
    // `inertia` is a lumped torsional inertia (no tilt inertia to carry a gyroscopic moment).
    as.AddBody(node, GearBody{0.0, shaft.inertia.value_or(0.0), 0.0}, 0.0);
    for (int g : fixed) {
      const TrainGear& gear = spec.gears[static_cast<size_t>(g)];
      s.gear_node[static_cast<size_t>(g)] = node;
      gear_offset[static_cast<size_t>(g)] = gear.at.value_or(0.0);
      as.AddBodyAt(node, gear_offset[static_cast<size_t>(g)],
                   DiskBody(gear.gear, spec.materials.at(gear.gear.material)), w);
    }
    if (shaft.bearings.empty()) {
      as.AddSupport(node, opt.rigid_radial_stiffness, opt.rigid_axial_stiffness,
                    opt.rigid_tilt_stiffness, opt.rigid_damping);
      s.bearings.push_back({id, -1, 0.0, node, 0.0, opt.rigid_radial_stiffness,
                            opt.rigid_axial_stiffness, opt.rigid_damping,
                            opt.rigid_tilt_stiffness});
    }
    for (size_t b = 0; b < shaft.bearings.size(); ++b) {
      const BearingSpec& bearing = shaft.bearings[b];
      as.AddSupportAt(node, bearing.at, bearing.radial_stiffness, bearing.axial_stiffness,
                      bearing.tilt_stiffness, bearing.damping);
      s.bearings.push_back({id, static_cast<int>(b), bearing.at, node, bearing.at,
                            bearing.radial_stiffness, bearing.axial_stiffness, bearing.damping,
                            bearing.tilt_stiffness});
    }
  }
  // Loose gears: a node each, on its bearing at its position on the shaft (the shaft points are
  // found before any loose node exists, so none couples to another loose gear).
  std::vector<std::pair<int, double>> seat(spec.gears.size(), {-1, 0.0});
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    const TrainGear& gear = spec.gears[g];
    if (gear.mounting != Mounting::kLoose) continue;
    const int shaft = spec.ShaftIndex(gear.shaft);
    const double at = gear.at.value_or(0.0);
    const int rigid_node = shaft_node[static_cast<size_t>(shaft)];
    seat[g] = rigid_node >= 0 ? std::pair{rigid_node, at}
                              : std::pair{detail::NearestNode(s.nodes, shaft, at), 0.0};
  }
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    const TrainGear& gear = spec.gears[g];
    if (gear.mounting != Mounting::kLoose) continue;
    const int node = static_cast<int>(s.nodes.size());
    s.nodes.push_back({spec.ShaftIndex(gear.shaft), gear.at.value_or(0.0)});
    s.gear_node[g] = node;
    as.AddBody(node, DiskBody(gear.gear, spec.materials.at(gear.gear.material)),
               spin(topo.gear_body[g]));
    as.AddCoupling(node, seat[g].first, seat[g].second, options.loose_radial_stiffness,
                   options.loose_axial_stiffness, options.loose_tilt_stiffness,
                   options.loose_damping);
  }
  s.dofs = 6 * static_cast<int>(s.nodes.size());
  s.M = detail::ToSparse(s.dofs, as.m);
  s.C = detail::ToSparse(s.dofs, as.c);
  s.K = detail::ToSparse(s.dofs, as.k);
  s.G = detail::ToSparse(s.dofs, as.g);

  // Bodies of the nodes: an elastic or rigid shaft's nodes are its body; a loose gear's node its.
  s.node_body.resize(s.nodes.size());
  for (size_t n = 0; n < s.nodes.size(); ++n) s.node_body[n] = s.nodes[n].shaft;
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    if (spec.gears[g].mounting == Mounting::kLoose) {
      s.node_body[static_cast<size_t>(s.gear_node[g])] = topo.gear_body[g];
    }
  }
  const int bodies = static_cast<int>(topo.bodies.size());
  s.body_rotations = Eigen::MatrixXd::Zero(s.dofs, bodies);
  for (size_t n = 0; n < s.nodes.size(); ++n) {
    s.body_rotations(TrainStructure::Dof(static_cast<int>(n), kThz), s.node_body[n]) = 1.0;
  }

  for (size_t m = 0; m < train.meshes.size(); ++m) {
    const TrainMeshModel& mesh = train.meshes[m];
    TrainMeshVectors v;
    v.sense = topo.bodies[static_cast<size_t>(mesh.body_a)].speed > 0.0 ? 1.0 : -1.0;
    detail::LocalMeshVectors loa = detail::MeshLineOfAction(
        mesh.geometry, spec.gears[static_cast<size_t>(mesh.gear_a)].gear.hand, v.sense);
    const double angle = spec.meshes[m].center_line_angle;
    if (angle != 0.0) {
      // The mesh built along +x, turned about z to its line of centres: every (x, y) pair of a
      // generalised vector (translations and tilts of both gears) rotates with it.
      const Eigen::Rotation2Dd turn(angle);
      for (auto* local : {&loa.drive, &loa.back, &loa.friction_drive, &loa.friction_back}) {
        for (int base : {0, 6}) {
          for (int pair : {kUx, kThx}) {
            const Eigen::Vector2d xy =
                turn * Eigen::Vector2d((*local)[base + pair], (*local)[base + pair + 1]);
            (*local)[base + pair] = xy.x();
            (*local)[base + pair + 1] = xy.y();
          }
        }
      }
    }
    const int na = s.gear_node[static_cast<size_t>(mesh.gear_a)];
    const int nb = s.gear_node[static_cast<size_t>(mesh.gear_b)];
    // A loose gear's offset is 0 (its own node); a fixed gear on a rigid shaft sits at its `at`.
    const double da = spec.gears[static_cast<size_t>(mesh.gear_a)].mounting == Mounting::kLoose
                          ? 0.0
                          : gear_offset[static_cast<size_t>(mesh.gear_a)];
    const double db = spec.gears[static_cast<size_t>(mesh.gear_b)].mounting == Mounting::kLoose
                          ? 0.0
                          : gear_offset[static_cast<size_t>(mesh.gear_b)];
    for (auto [local, global] : {std::pair{&loa.drive, &v.v_drive},
                                 {&loa.back, &v.v_back},
                                 {&loa.friction_drive, &v.friction_drive},
                                 {&loa.friction_back, &v.friction_back}}) {
      *global = Eigen::VectorXd::Zero(s.dofs);
      detail::ScatterAt(local->head<6>(), na, da, *global);
      detail::ScatterAt(local->tail<6>(), nb, db, *global);
    }
    s.meshes.push_back(std::move(v));
    s.mean_stiffness.push_back(mesh.stiffness.mean);
    s.mesh_damping.push_back(mesh.Damping());
  }

  for (const TrainCouplingModel& c : train.couplings) s.coupled_bodies.emplace_back(c.body_a, c.body_b);
  s.free_rotations = FreeRotations(s, std::vector<bool>(s.meshes.size(), true));

  for (size_t b = 0; b < topo.bodies.size(); ++b) {
    const std::vector<int>& gears = topo.bodies[b].gears;
    if (!gears.empty()) {
      s.body_node.push_back(s.gear_node[static_cast<size_t>(gears.front())]);
    } else {
      s.body_node.push_back(
          static_cast<int>(std::find(s.node_body.begin(), s.node_body.end(), static_cast<int>(b)) -
                           s.node_body.begin()));
    }
  }

  // Static load: the input torque drives and every load resists, each at its body's node, as a
  // moment about z in the body's sense of rotation.
  s.static_force = Eigen::VectorXd::Zero(s.dofs);
  auto apply = [&](int body, double torque) {
    const TrainBody& b = topo.bodies[static_cast<size_t>(body)];
    const int node = s.body_node[static_cast<size_t>(body)];
    s.static_force[TrainStructure::Dof(node, kThz)] += (b.speed > 0.0 ? 1.0 : -1.0) * torque;
  };
  apply(topo.input_body, train.input_torque);
  // Each load's mean torques, and its viscous drag c w w^T on the bodies' rotations (w on th_z in
  // the structure's fixed frame: the body's direction times its entry in LoadAction's sense).
  std::vector<Eigen::Triplet<double>> drag;
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    const LoadAction action = ActionOfLoad(spec, topo, i);
    for (const LoadAction::Term& term : action.terms) apply(term.body, -term.resisting);
    if (!(action.viscous > 0.0)) continue;
    for (const LoadAction::Term& p : action.terms) {
      for (const LoadAction::Term& q : action.terms) {
        const auto dof = [&](int body) {
          return TrainStructure::Dof(s.body_node[static_cast<size_t>(body)], kThz);
        };
        const auto sense = [&](int body) {
          return topo.bodies[static_cast<size_t>(body)].speed > 0.0 ? 1.0 : -1.0;
        };
        drag.emplace_back(
            dof(p.body), dof(q.body),
            action.viscous * p.direction * sense(p.body) * q.direction * sense(q.body));
      }
    }
  }
  if (!drag.empty()) {
    Eigen::SparseMatrix<double> c(s.dofs, s.dofs);
    c.setFromTriplets(drag.begin(), drag.end());
    s.C += c;
  }
  // Couplings: k and c on the twist th_z,a - th_z,b of their shafts' body nodes (the shafts turn
  // alike, so the fixed frame's twist is the running one up to one sign, which k w w^T drops).
  std::vector<Eigen::Triplet<double>> spring, damper;
  for (const TrainCouplingModel& c : train.couplings) {
    const int a = TrainStructure::Dof(s.body_node[static_cast<size_t>(c.body_a)], kThz);
    const int b = TrainStructure::Dof(s.body_node[static_cast<size_t>(c.body_b)], kThz);
    s.coupling_twist.push_back(Eigen::VectorXd::Zero(s.dofs));
    s.coupling_twist.back()[a] = 1.0;
    s.coupling_twist.back()[b] = -1.0;
    s.coupling_static_increment.push_back(c.StaticStiffness() - c.stiffness);
    for (auto [value, out] : {std::pair{c.stiffness, &spring}, std::pair{c.damping, &damper}}) {
      out->emplace_back(a, a, value);
      out->emplace_back(b, b, value);
      out->emplace_back(a, b, -value);
      out->emplace_back(b, a, -value);
    }
  }
  if (!spring.empty()) {
    Eigen::SparseMatrix<double> k(s.dofs, s.dofs), c(s.dofs, s.dofs);
    k.setFromTriplets(spring.begin(), spring.end());
    c.setFromTriplets(damper.begin(), damper.end());
    s.K += k;
    s.C += c;
  }
  return s;
}

}  // namespace gearnvh
