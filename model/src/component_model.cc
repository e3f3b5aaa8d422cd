#include "gearnvh/model/component_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/model/timoshenko_beam.h"

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

using Triplets = std::vector<Eigen::Triplet<double>>;

// The inclined line of action of a helical pair (see the header): the approach gains
// s tan(beta_b) times the relative axial displacement of the contact point, which the gears'
// axial translations and tilts produce through the contact points' arms rho x z.
void AddHelicalTerms(ComponentModel& m, Hand pinion_hand, double base_helix_angle,
                     const Eigen::Vector2d& n, const Eigen::Vector2d& nb) {
  const double s = (pinion_hand == Hand::kRight ? 1.0 : -1.0) * std::tan(base_helix_angle);
  const double rb1 = m.v_drive[m.PinionDof(kThz)], rb2 = m.v_drive[m.WheelDof(kThz)];
  for (Eigen::VectorXd* v : {&m.v_drive, &m.v_back}) {
    (*v)[m.PinionDof(kUz)] = s;
    (*v)[m.WheelDof(kUz)] = -s;
  }
  for (int d = 0; d < 2; ++d) {
    const NodeDof th = d == 0 ? kThx : kThy;
    // Drive contact points: pinion -r_b1 t, wheel +r_b2 t (rho x z = -r_b1 n, +r_b2 n); back
    // flank: pinion +r_b1 t_b, wheel -r_b2 t_b (rho x z = +r_b1 n_b, -r_b2 n_b).
    m.v_drive[m.PinionDof(th)] = -s * rb1 * n[d];
    m.v_drive[m.WheelDof(th)] = -s * rb2 * n[d];
    m.v_back[m.PinionDof(th)] = s * rb1 * nb[d];
    m.v_back[m.WheelDof(th)] = s * rb2 * nb[d];
  }
}

struct Assembler {
  Triplets m, c, k, g;
  void Add(Triplets& t, int i, int j, double v) {
    if (v != 0.0) t.emplace_back(i, j, v);
  }
  void AddBody(int node, const GearBody& b, double spin) {
    const int base = 6 * node;
    for (int d : {0, 1, 2}) Add(m, base + d, base + d, b.mass);
    Add(m, base + kThx, base + kThx, b.diametral);
    Add(m, base + kThy, base + kThy, b.diametral);
    Add(m, base + kThz, base + kThz, b.polar);
    // Disk gyroscopics per unit pinion speed: I_p [[0, 1], [-1, 0]] on (th_x, th_y) times spin.
    Add(g, base + kThx, base + kThy, spin * b.polar);
    Add(g, base + kThy, base + kThx, -spin * b.polar);
  }
  void AddSupport(int node, double radial, double axial, double tilt, double damping) {
    const int base = 6 * node;
    Add(k, base + kUx, base + kUx, radial);
    Add(k, base + kUy, base + kUy, radial);
    Add(k, base + kUz, base + kUz, axial);
    Add(k, base + kThx, base + kThx, tilt);
    Add(k, base + kThy, base + kThy, tilt);
    for (int d : {0, 1, 2}) Add(c, base + d, base + d, damping);
  }
};

// Nodes of one shaft: key points (ends, segment joints, gear, bearings, inertias), then subdivided.
std::vector<double> ShaftNodePositions(const ShaftSpec& shaft, const ComponentModelOptions& opt) {
  const double length = shaft.Length();
  std::vector<double> keys{0.0, length, shaft.gear_at};
  double z = 0.0, min_diameter = 1e300;
  for (const auto& s : shaft.segments) {
    z += s.length;
    keys.push_back(z);
    min_diameter = std::min(min_diameter, s.outer_diameter);
  }
  for (const auto& b : shaft.bearings) keys.push_back(b.at);
  for (const auto& i : shaft.inertias) keys.push_back(i.at);
  for (double& x : keys) x = std::clamp(x, 0.0, length);
  std::sort(keys.begin(), keys.end());
  std::vector<double> unique;
  for (double x : keys) {
    if (unique.empty() || x - unique.back() > 1e-9 * length) unique.push_back(x);
  }
  const double h = shaft.element_length.value_or(
      std::min(length / opt.default_elements_per_shaft, min_diameter));
  std::vector<double> nodes{unique.front()};
  for (size_t i = 1; i < unique.size(); ++i) {
    const double span = unique[i] - unique[i - 1];
    const int n = std::max(1, static_cast<int>(std::ceil(span / h - 1e-9)));
    for (int e = 1; e <= n; ++e) nodes.push_back(unique[i - 1] + span * e / n);
  }
  return nodes;
}

int NearestNode(const std::vector<FeNode>& nodes, int shaft, double z) {
  int best = -1;
  double best_d = 1e300;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].shaft != shaft) continue;
    const double d = std::abs(nodes[i].z - z);
    if (d < best_d) best_d = d, best = static_cast<int>(i);
  }
  return best;
}

const ShaftSegment& SegmentAt(const ShaftSpec& shaft, double z) {
  double end = 0.0;
  for (const auto& s : shaft.segments) {
    end += s.length;
    if (z <= end) return s;
  }
  return shaft.segments.back();
}

// Adds one shaft (or a rigid gear node); returns the gear node.
int AddShaft(const GearboxSpec& spec, const std::optional<ShaftSpec>& shaft, int shaft_id,
             const GearBody& body, double spin, const ComponentModelOptions& opt,
             std::vector<FeNode>& nodes, Assembler& as) {
  const int first = static_cast<int>(nodes.size());
  if (!shaft) {
    nodes.push_back({shaft_id, 0.0});
    as.AddBody(first, body, spin);
    as.AddSupport(first, opt.rigid_radial_stiffness, opt.rigid_axial_stiffness,
                  opt.rigid_tilt_stiffness, opt.rigid_damping);
    return first;
  }
  const Material& mat = spec.materials.at(shaft->material);
  for (double z : ShaftNodePositions(*shaft, opt)) nodes.push_back({shaft_id, z});
  const int last = static_cast<int>(nodes.size());
  for (int n = first; n + 1 < last; ++n) {
    const double l = nodes[n + 1].z - nodes[n].z;
    const ShaftSegment& seg = SegmentAt(*shaft, 0.5 * (nodes[n].z + nodes[n + 1].z));
    const BeamSection sec =
        BeamSection::Tube(seg.outer_diameter, seg.inner_diameter, mat.poisson_ratio);
    const BeamElementMatrices e = TimoshenkoBeamElement(sec, mat, l);
    for (int r = 0; r < 12; ++r) {
      for (int c = 0; c < 12; ++c) {
        const int gr = 6 * n + r, gc = 6 * n + c;
        as.Add(as.k, gr, gc, e.stiffness(r, c));
        as.Add(as.m, gr, gc, e.mass(r, c));
        as.Add(as.g, gr, gc, spin * e.gyroscopic(r, c));
      }
    }
  }
  const int gear_node = NearestNode(nodes, shaft_id, shaft->gear_at);
  as.AddBody(gear_node, body, spin);
  for (const auto& b : shaft->bearings) {
    as.AddSupport(NearestNode(nodes, shaft_id, b.at), b.radial_stiffness, b.axial_stiffness,
                  b.tilt_stiffness, b.damping);
  }
  for (const auto& in : shaft->inertias) {
    as.AddBody(NearestNode(nodes, shaft_id, in.at), GearBody{0.0, in.polar, in.diametral}, spin);
  }
  return gear_node;
}

Eigen::SparseMatrix<double> ToSparse(int n, const Triplets& t) {
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(t.begin(), t.end());
  s.makeCompressed();
  return s;
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
  const MeshPair pair = PairOf(spec);
  m.geometry = ComputePairGeometry(pair);
  const PairGeometry& g = m.geometry;
  const MeshEvaluator evaluator(pair, g, options.mesh);
  m.cycle = ComputeMeshCycle(pair, g, options.mesh);
  m.mesh_summary = SummarizeMeshCycle(m.cycle, g);
  m.segmentation = SegmentMeshCycle(pair, evaluator, spec.analysis.segments_per_cycle);
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
  m.M = ToSparse(m.dofs, as.m);
  m.C = ToSparse(m.dofs, as.c);
  m.K = ToSparse(m.dofs, as.k);
  m.G = ToSparse(m.dofs, as.g);

  const double aw = g.working_pressure_angle;
  const Eigen::Vector2d n(std::sin(aw), std::cos(aw)), nb(std::sin(aw), -std::cos(aw));
  const Eigen::Vector2d t(-n.y(), n.x()), tb(-nb.y(), nb.x());
  m.v_drive = Eigen::VectorXd::Zero(m.dofs);
  m.v_back = Eigen::VectorXd::Zero(m.dofs);
  m.translation_friction_drive = Eigen::VectorXd::Zero(m.dofs);
  m.translation_friction_back = Eigen::VectorXd::Zero(m.dofs);
  for (int d = 0; d < 2; ++d) {
    const NodeDof u = d == 0 ? kUx : kUy;
    m.v_drive[m.PinionDof(u)] = n[d];
    m.v_drive[m.WheelDof(u)] = -n[d];
    m.v_back[m.PinionDof(u)] = -nb[d];
    m.v_back[m.WheelDof(u)] = nb[d];
    m.translation_friction_drive[m.PinionDof(u)] = t[d];
    m.translation_friction_drive[m.WheelDof(u)] = -t[d];
    m.translation_friction_back[m.PinionDof(u)] = tb[d];
    m.translation_friction_back[m.WheelDof(u)] = -tb[d];
  }
  m.v_drive[m.PinionDof(kThz)] = m.v_back[m.PinionDof(kThz)] = rb1;
  m.v_drive[m.WheelDof(kThz)] = m.v_back[m.WheelDof(kThz)] = rb2;
  if (g.helix_angle > 0.0) AddHelicalTerms(m, spec.pinion.hand, g.base_helix_angle, n, nb);

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
  return m;
}

ModalSummary FullModelFrequencies(const ComponentModel& model, int count) {
  const Eigen::MatrixXd K = Eigen::MatrixXd(model.K) +
                            model.mesh_summary.mean * model.v_drive * model.v_drive.transpose();
  const NaturalModes modes = LowestNaturalModes(K, Eigen::MatrixXd(model.M), count);
  return {modes.frequencies_hz, modes.rigid_body_modes};
}

}  // namespace gearnvh
