// An independent reference for gear trains in quad precision (__float128, 113-bit mantissa), for
// the tests: on each grid segment (TrainGrid, the engine orders' states set to their values at the
// segment's start and carried by the exosystem, as the stepper; CVODE takes s(t) itself) the
// generator of the contact tuple from AssembleTrainGenerator (the
// CVODE reference's assembly, checked against the cache in train_stepper_test.cc), the state
// advanced by its Taylor series sum_k (A d)^k z / k!, kTerms terms on steps with rho(A) d <= 1/4
// (remainder below 4^-31 / 31!, far below quad rounding), every relevant gap of every mesh a
// polynomial on the step whose first crossing in its wall's direction is found by samples, the
// maximum between two samples (bisection on the derivative) and bisection to quad rounding. A
// state outside a wall at a grid boundary switches at once (with no tolerance). No part of the
// stepper's tables, decompositions or root finders is used. Rounding is ~1e-34: after the
// amplification of a rattle (1e3 per mesh cycle on a light loose gear) it stays far below
// double rounding, so a difference to the exact solver is the solver's.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh::testing {

struct QuadTrainResult {
  std::vector<double> te;            // sample-major, mesh-minor, m
  std::vector<ContactState> states;  // sample-major, mesh-minor
  std::vector<TrainReferenceEvent> events;
};

class QuadTrainReference {
 public:
  using Q = __float128;
  static constexpr int kTerms = 30;
  static constexpr int kSamples = 16;  // per step, for the root search

  explicit QuadTrainReference(const TrainTables& t) : t_(t), grid_(t) {}

  // From z0 in states0 at t = 0 to the last of `times` (increasing, > 0): TE and states there.
  QuadTrainResult Run(const Eigen::VectorXd& z0, const std::vector<ContactState>& states0,
                      const std::vector<double>& times) {
    const int m = t_.m;
    z_.assign(z0.data(), z0.data() + m);
    states_ = states0;
    taylor_.assign(kTerms + 1, std::vector<Q>(static_cast<size_t>(m)));
    QuadTrainResult out;
    size_t next = 0;
    Q time = 0;
    while (next < times.size()) {
      SetExcitation(grid_.start());
      SwitchOutside(time, out);
      Assemble();
      const Q segment_end = grid_.end();
      while (time < segment_end && next < times.size()) {
        const bool sample = static_cast<Q>(times[next]) <= segment_end;
        const Q stop = sample ? static_cast<Q>(times[next]) : segment_end;
        const bool last = time + step_ >= stop;
        const Q d = last ? stop - time : step_;
        Columns(d);
        int mesh = -1;
        ContactState to = ContactState::kFree;
        const Q s = FirstRoot(mesh, to);
        if (mesh >= 0) {
          Evaluate(s);
          time += s * d;
          out.events.push_back(
              {mesh, static_cast<double>(time), states_[static_cast<size_t>(mesh)], to});
          states_[static_cast<size_t>(mesh)] = to;
          Assemble();
          continue;
        }
        Evaluate(1);
        time = last ? stop : time + d;
        if (last && sample) {
          for (size_t i = 0; i < t_.meshes.size(); ++i)
            out.te.push_back(static_cast<double>(Delta(i, true)));
          out.states.insert(out.states.end(), states_.begin(), states_.end());
          ++next;
        }
      }
      if (time >= segment_end) grid_.Next();
    }
    return out;
  }

 private:
  // The orders' states at time t (then carried in quadruple precision by the generator's
  // exosystem, whose Taylor series is that of sin and cos).
  void SetExcitation(double time) {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(t_.m);
    t_.SetExcitation(time, z);
    for (int q = 0; q < t_.excitation_states(); ++q) {
      const int slot = t_.ExcitationSlot(0) + q;
      z_[static_cast<size_t>(slot)] = z[slot];
    }
  }
  void Assemble() {
    const Eigen::MatrixXd A = AssembleTrainGenerator(t_, grid_.segments(), states_);
    a_.assign(A.data(), A.data() + A.size());  // column-major
    const double rho = std::max(1.0, A.eigenvalues().cwiseAbs().maxCoeff());
    step_ = 0.25 / rho;
  }
  // taylor_[k] = (A d)^k z / k!.
  void Columns(Q d) {
    const size_t m = static_cast<size_t>(t_.m);
    taylor_[0] = z_;
    for (int k = 1; k <= kTerms; ++k) {
      std::vector<Q>& col = taylor_[static_cast<size_t>(k)];
      const std::vector<Q>& prev = taylor_[static_cast<size_t>(k - 1)];
      std::fill(col.begin(), col.end(), Q(0));
      for (size_t c = 0; c < m; ++c) {
        if (prev[c] == 0) continue;
        for (size_t r = 0; r < m; ++r) col[r] += a_[c * m + r] * prev[c];
      }
      for (Q& v : col) v *= d / k;
    }
  }
  void Evaluate(Q s) {
    for (size_t r = 0; r < z_.size(); ++r) {
      Q v = taylor_[kTerms][r];
      for (int k = kTerms - 1; k >= 0; --k) v = v * s + taylor_[static_cast<size_t>(k)][r];
      z_[r] = v;
    }
  }
  // v^T x (drive flank) or v_back^T x of mesh i at z_.
  Q Delta(size_t i, bool drive) const {
    const Eigen::VectorXd& v = t_.meshes[i].Vector(drive);
    Q d = 0;
    for (int r = 0; r < t_.n; ++r) d += static_cast<Q>(v[r]) * z_[static_cast<size_t>(r)];
    return d;
  }
  Q Wall(size_t i, bool drive) const {
    const TrainMeshTable& mt = t_.meshes[i];
    const Q e = mt.error[static_cast<size_t>(grid_.segments()[i])];
    return drive ? e + static_cast<Q>(mt.half_backlash) : e - static_cast<Q>(mt.half_backlash);
  }
  void SwitchOutside(Q time, QuadTrainResult& out) {
    for (size_t i = 0; i < t_.meshes.size(); ++i) {
      const Q gd = Delta(i, true) - Wall(i, true), gb = Delta(i, false) - Wall(i, false);
      ContactState to = states_[i];
      if (to == ContactState::kFree && gd > 0)
        to = ContactState::kDrive;
      else if (to == ContactState::kFree && gb < 0)
        to = ContactState::kBack;
      else if (to == ContactState::kDrive && gd < 0)
        to = ContactState::kFree;
      else if (to == ContactState::kBack && gb > 0)
        to = ContactState::kFree;
      if (to != states_[i]) {
        out.events.push_back({static_cast<int>(i), static_cast<double>(time), states_[i], to});
        states_[i] = to;
      }
    }
  }
  // The earliest crossing in (0, 1] (in units of the step) over every relevant wall; mesh -1 if
  // none. f = sign (g - wall) > 0 outside; a crossing is f rising through 0.
  Q FirstRoot(int& mesh, ContactState& to) const {
    Q best = 2;
    for (size_t i = 0; i < t_.meshes.size(); ++i) {
      struct W {
        bool drive;
        int sign;
        ContactState to;
      } walls[2];
      int count = 0;
      if (states_[i] == ContactState::kDrive) {
        walls[count++] = {true, -1, ContactState::kFree};
      } else if (states_[i] == ContactState::kBack) {
        walls[count++] = {false, 1, ContactState::kFree};
      } else {
        walls[count++] = {true, 1, ContactState::kDrive};
        walls[count++] = {false, -1, ContactState::kBack};
      }
      for (int w = 0; w < count; ++w) {
        Q c[kTerms + 1];
        const Eigen::VectorXd& v = t_.meshes[i].Vector(walls[w].drive);
        for (int k = 0; k <= kTerms; ++k) {
          Q s = 0;
          for (int r = 0; r < t_.n; ++r)
            s += static_cast<Q>(v[r]) * taylor_[static_cast<size_t>(k)][static_cast<size_t>(r)];
          c[k] = s * walls[w].sign;
        }
        c[0] -= Wall(i, walls[w].drive) * walls[w].sign;
        // No crossing possible on [0, 1]: f(s) <= f(0) + sum_{k>=1} |c_k|.
        Q reach = c[0];
        for (int k = 1; k <= kTerms; ++k) reach += c[k] < 0 ? -c[k] : c[k];
        if (reach <= 0) continue;
        const Q root = FirstCrossing(c);
        if (root < best) {
          best = root;
          mesh = static_cast<int>(i);
          to = walls[w].to;
        }
      }
    }
    return best;
  }
  static Q Value(const Q* c, Q s) {
    Q v = c[kTerms];
    for (int k = kTerms - 1; k >= 0; --k) v = v * s + c[k];
    return v;
  }
  static Q Slope(const Q* c, Q s) {
    Q v = kTerms * c[kTerms];
    for (int k = kTerms - 1; k >= 1; --k) v = v * s + k * c[k];
    return v;
  }
  // The first s in (0, 1] where f = Value(c, .) rises through 0 (2 if none): per sample interval
  // [a, b], f(b) > 0, or f' falling through 0 at an interior maximum with f > 0 there. The start
  // f(0) is not a crossing (right after an event f(0) is 0 to rounding, moving inside).
  static Q FirstCrossing(const Q* c) {
    for (int j = 0; j < kSamples; ++j) {
      Q a = Q(j) / kSamples, b = Q(j + 1) / kSamples;
      if (!(Value(c, b) > 0)) {
        if (!(Slope(c, a) > 0 && Slope(c, b) < 0)) continue;
        Q l = a, r = b;
        for (int it = 0; it < 120; ++it) {
          const Q mid = (l + r) / 2;
          if (Slope(c, mid) > 0)
            l = mid;
          else
            r = mid;
        }
        if (!(Value(c, l) > 0)) continue;
        b = l;
      }
      if (Value(c, a) > 0) {  // f(0) > 0 and f rising: outside from the start
        if (j > 0 || Slope(c, a) > 0) return a;
        continue;
      }
      for (int it = 0; it < 120; ++it) {
        const Q mid = (a + b) / 2;
        if (Value(c, mid) > 0)
          b = mid;
        else
          a = mid;
      }
      return b;
    }
    return 2;
  }

  const TrainTables& t_;
  TrainGrid grid_;
  std::vector<Q> z_, a_;
  std::vector<std::vector<Q>> taylor_;
  std::vector<ContactState> states_;
  Q step_ = 0;
};

}  // namespace gearnvh::testing
