#include "structure_assembly.h"

#include <algorithm>
#include <cmath>

#include "gearnvh/model/timoshenko_beam.h"

namespace gearnvh::detail {

Matrix6 OffsetTransform(double d) {
  Matrix6 t = Matrix6::Identity();
  t(kUx, kThy) = d;
  t(kUy, kThx) = -d;
  return t;
}

void Assembler::AddBody(int node, const GearBody& b, double spin) {
  const int base = 6 * node;
  for (int d : {0, 1, 2}) Add(m, base + d, base + d, b.mass);
  Add(m, base + kThx, base + kThx, b.diametral);
  Add(m, base + kThy, base + kThy, b.diametral);
  Add(m, base + kThz, base + kThz, b.polar);
  // Disk gyroscopics per unit input speed: I_p [[0, 1], [-1, 0]] on (th_x, th_y) times spin.
  Add(g, base + kThx, base + kThy, spin * b.polar);
  Add(g, base + kThy, base + kThx, -spin * b.polar);
}

void Assembler::AddSupport(int node, double radial, double axial, double tilt, double damping) {
  const int base = 6 * node;
  Add(k, base + kUx, base + kUx, radial);
  Add(k, base + kUy, base + kUy, radial);
  Add(k, base + kUz, base + kUz, axial);
  Add(k, base + kThx, base + kThx, tilt);
  Add(k, base + kThy, base + kThy, tilt);
  for (int d : {0, 1, 2}) Add(c, base + d, base + d, damping);
}

void Assembler::AddLocal(Triplets& t, int node, double d, const Matrix6& A) {
  const Matrix6 T = OffsetTransform(d);
  const Matrix6 B = T.transpose() * A * T;
  for (int r = 0; r < 6; ++r) {
    for (int col = 0; col < 6; ++col) Add(t, 6 * node + r, 6 * node + col, B(r, col));
  }
}

void Assembler::AddBodyAt(int node, double d, const GearBody& b, double spin) {
  if (d == 0.0) return AddBody(node, b, spin);
  Matrix6 mass = Matrix6::Zero(), gyro = Matrix6::Zero();
  mass.diagonal() << b.mass, b.mass, b.mass, b.diametral, b.diametral, b.polar;
  gyro(kThx, kThy) = spin * b.polar;
  gyro(kThy, kThx) = -spin * b.polar;
  AddLocal(m, node, d, mass);
  AddLocal(g, node, d, gyro);
}

void Assembler::AddSupportAt(int node, double d, double radial, double axial, double tilt,
                             double damping) {
  if (d == 0.0) return AddSupport(node, radial, axial, tilt, damping);
  Matrix6 stiff = Matrix6::Zero(), damp = Matrix6::Zero();
  stiff.diagonal() << radial, radial, axial, tilt, tilt, 0.0;
  damp.diagonal() << damping, damping, damping, 0.0, 0.0, 0.0;
  AddLocal(k, node, d, stiff);
  AddLocal(c, node, d, damp);
}

void Assembler::AddCoupling(int a, int b, double d, double radial, double axial, double tilt,
                            double damping) {
  // Relative motion r = q_a - T(d) q_b; energy r^T S r / 2.
  Matrix6 stiff = Matrix6::Zero(), damp = Matrix6::Zero();
  stiff.diagonal() << radial, radial, axial, tilt, tilt, 0.0;
  damp.diagonal() << damping, damping, damping, 0.0, 0.0, 0.0;
  const Matrix6 T = OffsetTransform(d);
  for (auto [target, S] : {std::pair{&k, &stiff}, std::pair{&c, &damp}}) {
    const Matrix6 ab = -*S * T, bb = T.transpose() * *S * T;
    for (int r = 0; r < 6; ++r) {
      for (int col = 0; col < 6; ++col) {
        Add(*target, 6 * a + r, 6 * a + col, (*S)(r, col));
        Add(*target, 6 * a + r, 6 * b + col, ab(r, col));
        Add(*target, 6 * b + col, 6 * a + r, ab(r, col));
        Add(*target, 6 * b + r, 6 * b + col, bb(r, col));
      }
    }
  }
}

std::vector<double> ShaftNodePositions(const ShaftSpec& shaft, const std::vector<double>& gears,
                                       int default_elements_per_shaft) {
  const double length = shaft.Length();
  std::vector<double> keys{0.0, length};
  keys.insert(keys.end(), gears.begin(), gears.end());
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
  const double h =
      shaft.element_length.value_or(std::min(length / default_elements_per_shaft, min_diameter));
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

namespace {

const ShaftSegment& SegmentAt(const ShaftSpec& shaft, double z) {
  double end = 0.0;
  for (const auto& s : shaft.segments) {
    end += s.length;
    if (z <= end) return s;
  }
  return shaft.segments.back();
}

}  // namespace

int AddShaftElements(const ShaftSpec& shaft, const Material& mat, int shaft_id,
                     const std::vector<double>& gears, double spin, int default_elements_per_shaft,
                     std::vector<FeNode>& nodes, Assembler& as) {
  const int first = static_cast<int>(nodes.size());
  for (double z : ShaftNodePositions(shaft, gears, default_elements_per_shaft)) {
    nodes.push_back({shaft_id, z});
  }
  const int last = static_cast<int>(nodes.size());
  for (int n = first; n + 1 < last; ++n) {
    const double l = nodes[n + 1].z - nodes[n].z;
    const ShaftSegment& seg = SegmentAt(shaft, 0.5 * (nodes[n].z + nodes[n + 1].z));
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
  return first;
}

void AddShaftSupports(const ShaftSpec& shaft, int shaft_id, double spin,
                      const std::vector<FeNode>& nodes, Assembler& as) {
  for (const auto& b : shaft.bearings) {
    as.AddSupport(NearestNode(nodes, shaft_id, b.at), b.radial_stiffness, b.axial_stiffness,
                  b.tilt_stiffness, b.damping);
  }
  for (const auto& in : shaft.inertias) {
    as.AddBody(NearestNode(nodes, shaft_id, in.at), GearBody{in.mass, in.polar, in.diametral},
               spin);
  }
}

Eigen::SparseMatrix<double> ToSparse(int n, const Triplets& t) {
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(t.begin(), t.end());
  s.makeCompressed();
  return s;
}

LocalMeshVectors MeshLineOfAction(const PairGeometry& geometry, Hand hand_a, double sense) {
  LocalMeshVectors out;
  out.drive.setZero();
  out.back.setZero();
  out.friction_drive.setZero();
  out.friction_back.setZero();
  const double aw = geometry.working_pressure_angle;
  const double rb1 = geometry.pinion.base, rb2 = geometry.wheel.base;
  const Eigen::Vector2d n(std::sin(aw), sense * std::cos(aw)),
      nb(std::sin(aw), -sense * std::cos(aw));
  // Friction along the flank, mirrored with the mesh: t = sense (z x n).
  const Eigen::Vector2d t(-sense * n.y(), sense * n.x()), tb(-sense * nb.y(), sense * nb.x());
  constexpr int b = 6;  // gear b's block
  for (int d = 0; d < 2; ++d) {
    const int u = d == 0 ? kUx : kUy;
    out.drive[u] = n[d];
    out.drive[b + u] = -n[d];
    out.back[u] = -nb[d];
    out.back[b + u] = nb[d];
    out.friction_drive[u] = t[d];
    out.friction_drive[b + u] = -t[d];
    out.friction_back[u] = tb[d];
    out.friction_back[b + u] = -tb[d];
  }
  out.drive[kThz] = out.back[kThz] = sense * rb1;
  out.drive[b + kThz] = out.back[b + kThz] = sense * rb2;
  if (geometry.helix_angle > 0.0) {
    // The inclined line of action: s times the relative axial displacement of the contact points
    // (component_model.h); the contact arms mirror with the mesh, hence sense s on the tilts.
    const double s =
        sense * (hand_a == Hand::kRight ? 1.0 : -1.0) * std::tan(geometry.base_helix_angle);
    for (auto* v : {&out.drive, &out.back}) {
      (*v)[kUz] = s;
      (*v)[b + kUz] = -s;
    }
    for (int d = 0; d < 2; ++d) {
      const int th = d == 0 ? kThx : kThy;
      out.drive[th] = -sense * s * rb1 * n[d];
      out.drive[b + th] = -sense * s * rb2 * n[d];
      out.back[th] = sense * s * rb1 * nb[d];
      out.back[b + th] = sense * s * rb2 * nb[d];
    }
  }
  return out;
}

void ScatterAt(const Vector6& local, int node, double d, Eigen::VectorXd& global) {
  const Vector6 f = OffsetTransform(d).transpose() * local;
  for (int i = 0; i < 6; ++i) global[6 * node + i] += f[i];
}

}  // namespace gearnvh::detail
