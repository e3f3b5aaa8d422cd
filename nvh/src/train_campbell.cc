#include "gearnvh/nvh/train_campbell.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace gearnvh {

std::vector<OrderLine> TrainOrderLines(const TrainSpec& spec, const GearTrain& train) {
  const TrainTopology& topo = train.topology;
  const double w_in = std::abs(topo.bodies[static_cast<size_t>(topo.input_body)].speed);
  std::vector<OrderLine> lines;
  for (const TrainBody& body : topo.bodies) {
    if (body.kind != BodyKind::kShaft || body.speed == 0.0) continue;  // a fixed shaft has none
    // Shafts at one speed (joined by a coupling) share one line.
    const double order = std::abs(body.speed) / w_in;
    const auto same = std::find_if(lines.begin(), lines.end(),
                                   [&](const OrderLine& l) { return SameOrder(l.order, order); });
    if (same == lines.end()) {
      lines.push_back({body.name + " 1x", order});
    } else {
      same->label.insert(same->label.size() - 3, ", " + body.name);
    }
  }
  for (const TrainMeshModel& mesh : train.meshes) {
    const double ratio = std::abs(topo.bodies[static_cast<size_t>(mesh.body_a)].speed) / w_in;
    const int z = spec.gears[static_cast<size_t>(mesh.gear_a)].gear.teeth;
    for (int h = 1; h <= 3; ++h) {
      // Harmonics of two meshes at one order (3 x 20 teeth, 2 x 30) share a line, as do shafts.
      AddOrderLine(lines, "mesh " + mesh.name + " " + std::to_string(h) + "x", h * z * ratio);
    }
  }
  std::vector<double> reference_orders;
  std::vector<ExcitationOrder> named = spec.operating.excitation;  // each named with its shaft
  for (size_t i = 0; i < named.size(); ++i) {
    reference_orders.push_back(ExcitationOrderOfInput(spec, topo, i));
    named[i].on = topo.bodies[static_cast<size_t>(ExcitationBody(spec, topo, i))].name;
  }
  AddExcitationLines(lines, named, reference_orders);
  return lines;
}

LinearRotorModel LinearisedTrain(const TrainStructure& s, const TrainReducedModel& reduced,
                                 const GearTrain& train) {
  LinearRotorModel r;
  r.M = reduced.M;
  r.K = reduced.K + CouplingStaticStiffness(s, reduced);
  r.C = reduced.C;
  r.G = reduced.G;
  for (size_t i = 0; i < reduced.v_drive.size(); ++i) {
    const Eigen::MatrixXd vv = reduced.v_drive[i] * reduced.v_drive[i].transpose();
    r.K += s.mean_stiffness[i] * vv;
    r.C += s.mesh_damping[i] * vv;
  }
  const Eigen::MatrixXd& T = reduced.recovery;
  // Kinetic-energy matrix of each DOF class of the physical model (torsional, lateral incl. tilts,
  // axial), in reduced coordinates, as LinearisedRotor does for the pair.
  const std::vector<std::vector<int>> classes{{kThz}, {kUx, kUy, kThx, kThy}, {kUz}};
  for (size_t c = 0; c < classes.size(); ++c) {
    auto in_class = [&](Eigen::Index dof) {
      const int d = static_cast<int>(dof % 6);
      for (int nd : classes[c]) {
        if (d == nd) return true;
      }
      return false;
    };
    std::vector<Eigen::Triplet<double>> entries;
    for (int outer = 0; outer < s.M.outerSize(); ++outer) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.M, outer); it; ++it) {
        if (in_class(it.row()) && in_class(it.col())) {
          entries.emplace_back(it.row(), it.col(), it.value());
        }
      }
    }
    Eigen::SparseMatrix<double> Mc(s.dofs, s.dofs);
    Mc.setFromTriplets(entries.begin(), entries.end());
    r.class_mass[c] = T.transpose() * (Mc * T);
  }
  for (size_t g = 0; g < s.gear_node.size(); ++g) {
    const int node = s.gear_node[g];
    const int body = train.topology.gear_body[g];
    const double spin = train.topology.bodies[static_cast<size_t>(body)].speed > 0.0 ? 1.0 : -1.0;
    r.disks.push_back(
        {T.row(TrainStructure::Dof(node, kUx)), T.row(TrainStructure::Dof(node, kUy)), spin});
  }
  return r;
}

CampbellData TrainCampbell(const TrainSpec& spec, const GearTrain& train,
                           const TrainStructure& structure, const TrainReducedModel& reduced,
                           const std::vector<double>& input_speeds,
                           const CampbellOptions& options) {
  return ComputeCampbell(LinearisedTrain(structure, reduced, train), input_speeds,
                         TrainOrderLines(spec, train), options);
}

}  // namespace gearnvh
