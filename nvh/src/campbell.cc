#include "gearnvh/nvh/campbell.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "gearnvh/model/input_error.h"

namespace gearnvh {

void CampbellOptions::Validate() const {
  if (!(max_frequency_hz > 0.0)) {
    throw InputError("CampbellOptions.max_frequency_hz", 0, std::to_string(max_frequency_hz),
                     "must be > 0");
  }
  if (!(class_threshold > 0.5 && class_threshold <= 1.0)) {
    throw InputError("CampbellOptions.class_threshold", 0, std::to_string(class_threshold),
                     "must be in (0.5, 1]");
  }
  if (!(min_frequency_hz >= 0.0)) {
    throw InputError("CampbellOptions.min_frequency_hz", 0, std::to_string(min_frequency_hz),
                     "must be >= 0");
  }
}

bool SameOrder(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(a, b); }

void AddOrderLine(std::vector<OrderLine>& lines, const std::string& label, double order) {
  const auto same = std::find_if(lines.begin(), lines.end(),
                                 [&](const OrderLine& l) { return SameOrder(l.order, order); });
  if (same == lines.end()) {
    lines.push_back({label, order});
  } else if (same->label.find(label) == std::string::npos) {
    same->label += " = " + label;
  }
}

void AddExcitationLines(std::vector<OrderLine>& lines,
                        const std::vector<ExcitationOrder>& excitation,
                        const std::vector<double>& reference_orders) {
  for (size_t i = 0; i < excitation.size(); ++i) {
    const ExcitationOrder& e = excitation[i];
    std::ostringstream label;
    label << "excitation " << e.order << "x" << (e.on.empty() ? "" : " " + e.on);
    AddOrderLine(lines, label.str(), reference_orders.empty() ? e.order : reference_orders[i]);
  }
}

std::vector<OrderLine> GearOrderLines(int pinion_teeth, int wheel_teeth,
                                      const std::vector<ExcitationOrder>& excitation) {
  std::vector<OrderLine> lines;
  for (int k = 1; k <= 3; ++k) {
    lines.push_back({std::to_string(k) + "x mesh", static_cast<double>(k * pinion_teeth)});
  }
  for (int k = 1; k <= 2; ++k) {
    lines.push_back({std::to_string(k) + "x pinion", static_cast<double>(k)});
    lines.push_back({std::to_string(k) + "x wheel",
                     static_cast<double>(k) * pinion_teeth / static_cast<double>(wheel_teeth)});
  }
  AddExcitationLines(lines, excitation);
  return lines;
}

const char* ModeTypeName(ModeType t) {
  switch (t) {
    case ModeType::kTorsional:
      return "torsional";
    case ModeType::kLateral:
      return "lateral";
    case ModeType::kAxial:
      return "axial";
    case ModeType::kCoupled:
      return "coupled";
    case ModeType::kUnknown:
      break;
  }
  return "unknown";
}

const char* WhirlName(Whirl w) {
  switch (w) {
    case Whirl::kForward:
      return "forward";
    case Whirl::kBackward:
      return "backward";
    case Whirl::kNone:
      break;
  }
  return "none";
}

std::string ModeInfo::Label() const {
  static const char* kClass[3] = {"torsional", "lateral", "axial"};
  std::string label = ModeTypeName(type);
  if (type == ModeType::kCoupled) {
    // The two largest energy classes, e.g. "coupled torsional-lateral".
    int a = 0;
    for (int c = 1; c < 3; ++c) {
      if (energy_fraction[c] > energy_fraction[a]) a = c;
    }
    int b = a == 0 ? 1 : 0;
    for (int c = 0; c < 3; ++c) {
      if (c != a && energy_fraction[c] > energy_fraction[b]) b = c;
    }
    label += std::string(" ") + kClass[std::min(a, b)] + "-" + kClass[std::max(a, b)];
  }
  if (whirl != Whirl::kNone) label += std::string(", ") + WhirlName(whirl) + " whirl";
  return label;
}

namespace {

struct Mode {
  double frequency_hz;
  double damping_ratio;
  Eigen::VectorXcd shape;  // displacement part, normalised
};

// M^-1 K, M^-1 C and M^-1 G, factorised once for the whole sweep.
struct FirstOrderBlocks {
  Eigen::MatrixXd stiffness, damping, gyroscopic;
};

std::vector<Mode> Modes(const FirstOrderBlocks& blocks, double speed, double min_hz) {
  const Eigen::Index n = blocks.stiffness.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -blocks.stiffness;
  A.bottomRightCorner(n, n) = -speed * blocks.gyroscopic;
  if (blocks.damping.size() > 0) A.bottomRightCorner(n, n) -= blocks.damping;
  Eigen::EigenSolver<Eigen::MatrixXd> eig(A, true);
  std::vector<Mode> modes;
  for (Eigen::Index i = 0; i < 2 * n; ++i) {
    const std::complex<double> lambda = eig.eigenvalues()[i];
    const double f = lambda.imag() / (2.0 * std::numbers::pi);
    if (lambda.imag() <= 0.0 || std::abs(lambda) / (2.0 * std::numbers::pi) < min_hz) continue;
    Eigen::VectorXcd shape = eig.eigenvectors().col(i).head(n);
    shape.normalize();
    modes.push_back({f, -lambda.real() / std::abs(lambda), std::move(shape)});
  }
  std::sort(modes.begin(), modes.end(),
            [](const Mode& a, const Mode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

double Mac(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  const double num = std::norm(a.dot(b));  // a^H b
  return num / (a.squaredNorm() * b.squaredNorm());
}

ModeInfo Identify(const LinearRotorModel& model, const Eigen::VectorXcd& shape, double threshold) {
  ModeInfo info;
  if (model.class_mass[0].size() == 0) return info;
  double total = 0.0;
  for (int c = 0; c < 3; ++c) {
    const std::complex<double> e = shape.dot(model.class_mass[c] * shape);  // phi^H M_c phi
    info.energy_fraction[c] = std::max(e.real(), 0.0);
    total += info.energy_fraction[c];
  }
  if (!(total > 0.0)) return info;
  for (double& f : info.energy_fraction) f /= total;
  info.type = ModeType::kCoupled;
  for (int c = 0; c < 3; ++c) {
    if (info.energy_fraction[c] >= threshold) info.type = static_cast<ModeType>(c);
  }
  double orbit = 0.0, amplitude = 0.0;
  for (const LinearRotorModel::Disk& d : model.disks) {
    const std::complex<double> x = (d.ux.cast<std::complex<double>>() * shape)(0);
    const std::complex<double> y = (d.uy.cast<std::complex<double>>() * shape)(0);
    orbit += d.spin * (x * std::conj(y)).imag();
    amplitude += std::norm(x) + std::norm(y);
  }
  if (amplitude > 0.0 && info.energy_fraction[1] >= 0.1 && std::abs(orbit) > 1e-3 * amplitude) {
    info.whirl = orbit > 0.0 ? Whirl::kForward : Whirl::kBackward;
  }
  return info;
}

}  // namespace

LinearRotorModel LinearisedRotor(const ComponentModel& model, const ReducedModel& reduced) {
  LinearRotorModel r;
  const double k = model.mesh_summary.mean;
  r.M = reduced.M;
  r.K = reduced.K + k * reduced.v_drive * reduced.v_drive.transpose();
  r.C = reduced.C + model.mesh_damping * reduced.v_drive * reduced.v_drive.transpose();
  r.G = reduced.G;
  const Eigen::MatrixXd& T = reduced.recovery;
  // Kinetic-energy matrix of each DOF class of the physical model, in reduced coordinates.
  const NodeDof classes[3][4] = {
      {kThz, kThz, kThz, kThz}, {kUx, kUy, kThx, kThy}, {kUz, kUz, kUz, kUz}};
  for (int c = 0; c < 3; ++c) {
    Eigen::SparseMatrix<double> Mc(model.dofs, model.dofs);
    std::vector<Eigen::Triplet<double>> entries;
    for (int outer = 0; outer < model.M.outerSize(); ++outer) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(model.M, outer); it; ++it) {
        auto in_class = [&](Eigen::Index dof) {
          const int d = static_cast<int>(dof % 6);
          for (NodeDof nd : classes[c]) {
            if (d == nd) return true;
          }
          return false;
        };
        if (in_class(it.row()) && in_class(it.col()))
          entries.emplace_back(it.row(), it.col(), it.value());
      }
    }
    Mc.setFromTriplets(entries.begin(), entries.end());
    r.class_mass[static_cast<size_t>(c)] = T.transpose() * (Mc * T);
  }
  for (auto [node, spin] : {std::pair{model.pinion_node, 1.0}, {model.wheel_node, -1.0}}) {
    r.disks.push_back(
        {T.row(ComponentModel::Dof(node, kUx)), T.row(ComponentModel::Dof(node, kUy)), spin});
  }
  return r;
}

CampbellData ComputeCampbell(const LinearRotorModel& model, const std::vector<double>& speeds,
                             const std::vector<OrderLine>& orders, const CampbellOptions& options) {
  options.Validate();
  CampbellData data;
  data.speeds_rad_s = speeds;
  data.orders = orders;
  if (speeds.empty()) return data;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::LDLT<Eigen::MatrixXd> mass(model.M);
  const FirstOrderBlocks blocks{mass.solve(model.K),
                                model.C.size() > 0 ? mass.solve(model.C) : Eigen::MatrixXd(),
                                mass.solve(model.G)};
  // Every mode that can come below max_frequency_hz: gyroscopic stiffening can lower a backward
  // mode by a large factor over a sweep, so all modes are tracked and those that never come below
  // the limit are dropped at the end.
  std::vector<Eigen::VectorXcd> tracked;
  for (size_t s = 0; s < speeds.size(); ++s) {
    const std::vector<Mode> modes = Modes(blocks, speeds[s], options.min_frequency_hz);
    if (s == 0) {
      const size_t count = modes.size();
      data.frequency_hz.assign(count, std::vector<double>(speeds.size(), nan));
      data.mac.assign(count, std::vector<double>(speeds.size(), nan));
      data.damping_ratio.assign(count, std::vector<double>(speeds.size(), nan));
      for (size_t k = 0; k < count; ++k) {
        tracked.push_back(modes[k].shape);
        data.frequency_hz[k][0] = modes[k].frequency_hz;
        data.damping_ratio[k][0] = modes[k].damping_ratio;
        data.mac[k][0] = 1.0;
      }
      continue;
    }
    // Greedy global assignment on the MAC matrix (tracks x candidates).
    const size_t tracks = tracked.size();
    std::vector<std::vector<double>> mac(tracks, std::vector<double>(modes.size()));
    for (size_t k = 0; k < tracks; ++k)
      for (size_t c = 0; c < modes.size(); ++c) mac[k][c] = Mac(tracked[k], modes[c].shape);
    std::vector<bool> track_done(tracks, false), cand_used(modes.size(), false);
    for (size_t round = 0; round < std::min(tracks, modes.size()); ++round) {
      double best = -1.0;
      size_t bk = 0, bc = 0;
      for (size_t k = 0; k < tracks; ++k) {
        if (track_done[k]) continue;
        for (size_t c = 0; c < modes.size(); ++c) {
          if (!cand_used[c] && mac[k][c] > best) best = mac[k][c], bk = k, bc = c;
        }
      }
      if (best < 0.0) break;
      track_done[bk] = cand_used[bc] = true;
      data.frequency_hz[bk][s] = modes[bc].frequency_hz;
      data.damping_ratio[bk][s] = modes[bc].damping_ratio;
      data.mac[bk][s] = best;
      tracked[bk] = modes[bc].shape;
    }
  }
  // Keep the modes that come below the limit somewhere, in order of their first frequency.
  std::vector<size_t> keep;
  for (size_t k = 0; k < data.frequency_hz.size(); ++k) {
    double lowest = std::numeric_limits<double>::infinity();
    for (double f : data.frequency_hz[k]) {
      if (!std::isnan(f)) lowest = std::min(lowest, f);
    }
    if (lowest <= options.max_frequency_hz) keep.push_back(k);
  }
  if (keep.empty() && !data.frequency_hz.empty()) keep.push_back(0);  // the lowest mode
  CampbellData kept;
  kept.speeds_rad_s = data.speeds_rad_s;
  kept.orders = data.orders;
  for (size_t k : keep) {
    kept.frequency_hz.push_back(data.frequency_hz[k]);
    kept.mac.push_back(data.mac[k]);
    kept.damping_ratio.push_back(data.damping_ratio[k]);
    // Identified at the highest speed (largest gyroscopic split): tracked[k] is that shape.
    kept.modes.push_back(Identify(model, tracked[k], options.class_threshold));
  }
  data = std::move(kept);
  // Critical speeds: sign changes of f_mode(Omega) - order Omega / 2 pi.
  for (const OrderLine& line : orders) {
    for (size_t k = 0; k < data.frequency_hz.size(); ++k) {
      for (size_t s = 1; s < speeds.size(); ++s) {
        const double f0 = data.frequency_hz[k][s - 1], f1 = data.frequency_hz[k][s];
        if (std::isnan(f0) || std::isnan(f1)) continue;
        const double d0 = f0 - line.order * speeds[s - 1] / (2.0 * std::numbers::pi);
        const double d1 = f1 - line.order * speeds[s] / (2.0 * std::numbers::pi);
        if (d0 == 0.0 || (d0 > 0.0) == (d1 > 0.0)) continue;
        const double u = d0 / (d0 - d1);
        CriticalSpeed c;
        c.order = line.label;
        c.mode = static_cast<int>(k);
        c.speed_rad_s = speeds[s - 1] + u * (speeds[s] - speeds[s - 1]);
        c.speed_rpm = c.speed_rad_s * 60.0 / (2.0 * std::numbers::pi);
        c.frequency_hz = line.order * c.speed_rad_s / (2.0 * std::numbers::pi);
        data.critical_speeds.push_back(c);
      }
    }
  }
  std::sort(
      data.critical_speeds.begin(), data.critical_speeds.end(),
      [](const CriticalSpeed& a, const CriticalSpeed& b) { return a.speed_rad_s < b.speed_rad_s; });
  return data;
}

}  // namespace gearnvh
