#include "gearnvh/model/component_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/model/shaft_misalignment.h"
#include "structure_assembly.h"

namespace gearnvh {

void ComponentModelOptions::Validate() const {
  mesh.Validate();
  auto positive = [](const char* name, double v) {
    if (!(v > 0.0))
      throw InputError(std::string("ComponentModelOptions.") + name, 0, std::to_string(v),
                       "must be > 0");
  };
  positive("rigid_radial_stiffness", rigid_radial_stiffness);
  positive("rigid_axial_stiffness", rigid_axial_stiffness);
  positive("rigid_tilt_stiffness", rigid_tilt_stiffness);
  if (!(rigid_damping >= 0.0)) {
    throw InputError("ComponentModelOptions.rigid_damping", 0, std::to_string(rigid_damping),
                     "must be >= 0");
  }
  if (default_elements_per_shaft < 2) {
    throw InputError("ComponentModelOptions.default_elements_per_shaft", 0,
                     std::to_string(default_elements_per_shaft), "must be >= 2");
  }
}

GearBody DiskBody(const GearSpec& gear, const Material& material) {
  // The pitch radius of the transverse section (m_t = m_n / cos beta).
  const double rp = 0.5 * gear.module / std::cos(gear.helix_angle) * gear.teeth;
  const double rb = 0.5 * gear.bore_diameter;
  const double L = gear.face_width;
  GearBody body;
  body.mass = gear.mass.value_or(material.density * std::numbers::pi * (rp * rp - rb * rb) * L);
  body.polar = gear.inertia.value_or(0.5 * body.mass * (rp * rp + rb * rb));
  body.diametral = 0.5 * body.polar + body.mass * L * L / 12.0;
  return body;
}

namespace {

using detail::Assembler;

// Adds one shaft (or a rigid gear node); returns the gear node.
int AddShaft(const GearboxSpec& spec, const std::optional<ShaftSpec>& shaft, int shaft_id,
             const GearBody& body, double spin, const ComponentModelOptions& opt,
             std::vector<FeNode>& nodes, Assembler& as) {
  if (!shaft) {
    const int node = static_cast<int>(nodes.size());
    nodes.push_back({shaft_id, 0.0});
    as.AddBody(node, body, spin);
    as.AddSupport(node, opt.rigid_radial_stiffness, opt.rigid_axial_stiffness,
                  opt.rigid_tilt_stiffness, opt.rigid_damping);
    return node;
  }
  detail::AddShaftElements(*shaft, spec.materials.at(shaft->material), shaft_id, {shaft->gear_at},
                           spin, opt.default_elements_per_shaft, nodes, as);
  const int gear_node = detail::NearestNode(nodes, shaft_id, shaft->gear_at);
  as.AddBody(gear_node, body, spin);
  detail::AddShaftSupports(*shaft, shaft_id, spin, nodes, as);
  return gear_node;
}

// The mesh's cycle, segments, summary and error excitation for `pair` (m.geometry set).
void BuildMesh(const GearboxSpec& spec, const MeshPair& pair, const ComponentModelOptions& options,
               ComponentModel& m) {
  const PairGeometry& g = m.geometry;
  const MeshEvaluator evaluator(pair, g, options.mesh);
  m.cycle = ComputeMeshCycle(pair, g, options.mesh);
  m.segmentation = SegmentMeshCycle(pair, evaluator, spec.analysis.segments_per_cycle);
  m.mesh_summary = SummarizeMeshCycle(m.cycle, g, m.segmentation);
  m.warnings = m.cycle.warnings;
  m.errors = MeshErrorExcitation(pair, m.segmentation);
  if (m.errors.active() && m.mesh_summary.max > 0.0) {
    const double pair_deflection = m.cycle.load / m.mesh_summary.max;
    if (m.errors.largest_pair_deviation() > pair_deflection) {
      char text[320];
      std::snprintf(text, sizeof text,
                    "pitch deviations differ by up to %.3g µm, more than the loaded deflection of "
                    "the mesh (%.3g µm at the operating load): they can unload tooth pairs, which "
                    "the model does not follow (the loaded pairs of the error-free mesh carry the "
                    "errors' mean)",
                    m.errors.largest_pair_deviation() * 1e6, pair_deflection * 1e6);
      m.warnings.push_back(text);
    }
  }
}

}  // namespace

Eigen::VectorXd ComponentModel::FrictionVector(Flank flank, double sigma, double arm_pinion,
                                               double arm_wheel) const {
  Eigen::VectorXd w =
      sigma * (flank == Flank::kDrive ? translation_friction_drive : translation_friction_back);
  w[PinionDof(kThz)] += arm_pinion;
  w[WheelDof(kThz)] += arm_wheel;
  return w;
}

ComponentModel BuildComponentModel(const GearboxSpec& spec, const ComponentModelOptions& options) {
  options.Validate();
  ComponentModel m;
  MeshPair pair = PairOf(spec);
  m.geometry = ComputePairGeometry(pair);
  const PairGeometry& g = m.geometry;
  BuildMesh(spec, pair, options, m);
  m.half_backlash = 0.5 * spec.mesh.backlash;
  m.friction_coefficient = spec.mesh.friction_coefficient;
  m.pinion_speed = spec.operating.speed;
  m.flexible = spec.input_shaft.has_value() || spec.output_shaft.has_value();

  m.pinion_body = DiskBody(spec.pinion, spec.MaterialOf(spec.pinion));
  m.wheel_body = DiskBody(spec.wheel, spec.MaterialOf(spec.wheel));
  const double rb1 = g.pinion.base, rb2 = g.wheel.base;
  const double j1 = m.pinion_body.polar, j2 = m.wheel_body.polar;
  m.effective_mass = j1 * j2 / (j1 * rb2 * rb2 + j2 * rb1 * rb1);
  m.mesh_damping =
      2.0 * spec.mesh.damping_ratio * std::sqrt(m.mesh_summary.mean * m.effective_mass);

  Assembler as;
  m.pinion_node = AddShaft(spec, spec.input_shaft, 0, m.pinion_body, 1.0, options, m.nodes, as);
  m.wheel_node =
      AddShaft(spec, spec.output_shaft, 1, m.wheel_body, -rb1 / rb2, options, m.nodes, as);
  m.dofs = 6 * static_cast<int>(m.nodes.size());
  m.M = detail::ToSparse(m.dofs, as.m);
  m.C = detail::ToSparse(m.dofs, as.c);
  m.K = detail::ToSparse(m.dofs, as.k);
  m.G = detail::ToSparse(m.dofs, as.g);

  // The schema-1 pinion turns about +z (sense +1).
  const detail::LocalMeshVectors loa = detail::MeshLineOfAction(g, spec.pinion.hand, 1.0);
  m.v_drive = Eigen::VectorXd::Zero(m.dofs);
  m.v_back = Eigen::VectorXd::Zero(m.dofs);
  m.translation_friction_drive = Eigen::VectorXd::Zero(m.dofs);
  m.translation_friction_back = Eigen::VectorXd::Zero(m.dofs);
  for (auto [local, global] : {std::pair{&loa.drive, &m.v_drive},
                               {&loa.back, &m.v_back},
                               {&loa.friction_drive, &m.translation_friction_drive},
                               {&loa.friction_back, &m.translation_friction_back}}) {
    detail::ScatterAt(local->head<6>(), m.pinion_node, 0.0, *global);
    detail::ScatterAt(local->tail<6>(), m.wheel_node, 0.0, *global);
  }

  // Polar inertia rotating with each gear: 1^T M_thz,thz 1 over that shaft's torsion DOFs.
  for (int k = 0; k < m.M.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m.M, k); it; ++it) {
      if (it.row() % 6 != kThz || it.col() % 6 != kThz) continue;
      const int shaft_r = m.nodes[it.row() / 6].shaft, shaft_c = m.nodes[it.col() / 6].shaft;
      if (shaft_r != shaft_c) continue;
      (shaft_r == 0 ? m.pinion_side_inertia : m.wheel_side_inertia) += it.value();
    }
  }
  m.static_force = Eigen::VectorXd::Zero(m.dofs);
  m.static_force[m.PinionDof(kThz)] = spec.WheelTorque() * rb1 / rb2;
  m.static_force[m.WheelDof(kThz)] = spec.WheelTorque();

  // Elastic shafts tilt the gears under the static load: the mesh again with that misalignment.
  if (m.flexible && m.cycle.load > 0.0) {
    // The free rotation: the pinion's shaft turning by r_b2 against the wheel's by -r_b1.
    Eigen::MatrixXd free = Eigen::MatrixXd::Zero(m.dofs, 1);
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      free(ComponentModel::Dof(static_cast<int>(i), kThz), 0) = m.nodes[i].shaft == 0 ? rb2 : -rb1;
    }
    free.normalize();
    const Eigen::SparseVector<double> v = m.v_drive.sparseView();
    const Eigen::SparseMatrix<double> engaged =
        m.K + m.mesh_summary.mean * Eigen::SparseMatrix<double>(v * v.transpose());
    const Eigen::VectorXd x = StaticDeflection(engaged, m.static_force, free);
    pair.shaft_misalignment =
        TiltMisalignment(m.v_drive, x, m.pinion_node, m.wheel_node, pair.face_width);
    if (pair.shaft_misalignment != 0.0) {
      BuildMesh(spec, pair, options, m);
      m.mesh_damping =
          2.0 * spec.mesh.damping_ratio * std::sqrt(m.mesh_summary.mean * m.effective_mass);
    }
  }
  return m;
}

ModalSummary FullModelFrequencies(const ComponentModel& model, int count) {
  const Eigen::MatrixXd K = Eigen::MatrixXd(model.K) +
                            model.mesh_summary.mean * model.v_drive * model.v_drive.transpose();
  const double k = model.mesh_summary.mean;
  const NaturalModes modes = LowestNaturalModes(
      K, Eigen::MatrixXd(model.M), count, false,
      [&](const Eigen::VectorXd& x) { return FullStrainMagnitude(model, k, x); });
  return {modes.frequencies_hz, modes.rigid_body_modes};
}

double FullStrainMagnitude(const ComponentModel& model, double mesh_stiffness,
                           const Eigen::VectorXd& x) {
  const double mesh = model.v_drive.cwiseAbs().dot(x.cwiseAbs());
  return AbsoluteQuadraticForm(model.K, x) + std::abs(mesh_stiffness) * mesh * mesh;
}

}  // namespace gearnvh
