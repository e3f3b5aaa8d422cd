// Segment-run fusion on gear trains (docs/solver.md "Segment-run fusion", docs/gear-trains.md):
// products of 2, 4, ..., 2^L consecutive grid segments of the common period, in one contact
// combination, used when a certificate proves that no wall of any mesh is reached over the run.
//
// Run. At grid position p of the common period (p a multiple of r = 2^l, p + r <= G, G the
// period's grid segments) the stepper sets the input slots to u_i (the engine orders' states and
// the errors' means, SetInputs) at each grid segment start and applies expm(A_i h_i). With Pi = I
// on every slot but the inputs' (cleared), that is affine in z and in the u_i:
//   z_end = P Pi z + sum_i U_i u_i,   P = Phi_{r-1} Pi ... Phi_0 Pi,   Phi_i = expm(A_i h_i)
// (balanced Pade, as the cycle map), U_i (m x p) the images of the slots set at grid segment i.
// Built lazily per (contact combination, position, level) from the grid segments' tuples and
// lengths at the first visit (later periods' lengths differ from those by the rounding of the
// absolute time, |dh| <= 4 eps t), held while the tables' bytes stay within a limit.
//
// Certificate, per wall of every mesh (g = Vector(drive)^T x - Wall, sigma g > 0 outside;
// sigma = -1 for drive's g+, +1 for back's g-; a free mesh has both walls): with c = sigma
// Vector(drive)^T on the positions, f(t) = c x(t) and w(t) = f(t) - sigma Wall_static(t) over the
// run [0, D] (Wall_static = e_ij +- b_i of the grid segment; the error input's part u_i of the
// wall is added at the end),
//   sup w <= max_k w(t_k) + max_k d_k^2 / 8 sup_{[t_k, t_k + d_k]} |f''|   (chord bound: f is C^2
// on each sub-step t_k .. t_k + d_k of a grid segment and C^1 across grid boundaries; the static
// wall is constant on a grid segment and the nodes include its ends),
//   sup |f''| <= |f''(t_k)| + d_k sup |f'''|,
//   f'''(t_k + s) = c A^3 e^{As} (z_k - e_g) + c A^2 e^{As} rho_g,
// e_g the grid segment's static equilibrium (A e_g = rho_g, rounding and friction's inconsistency
// along the free rotation; z_k - e_g has no constant part, which e^{As} keeps), so
//   |f'''| <= e^q (||c A^3 S^-1||_1' ||S (z_k - e_g)||_inf + ||c A^2 S^-1||_1 ||S rho_g||_inf),
// S = BalancingScale (positions 1, velocities 1 / w_ref, slots scaled to their forcing), ' the
// constant column left out, q = ||S A S^-1||_inf d_k <= 1 (sub-steps d_k = h / ceil(rate h);
// ||e^{Bs}||_inf <= e^{||B||_inf s}). Each node quantity is linear in the start state: with the
// free rotation removed (c A^p annihilates it and every A_i keeps it invariant; only its angle
// when a viscous drag damps its speed, which then counts as a deviation like any) and the slots
// cleared, x = L Pi z = y + dev for the run's reference y = e_0 (constant slot 1), z_k = F_k y +
// F_k dev + sum_iq G_iq(t_k) u_iq, so
//   w(t_k) <= c F_k y - sigma Wall_static + |c F_k| . |dev| + sum |c G_iq(t_k)| |u_iq|
// and |f''(t_k)| (rows c A^2 F_k, c A^2 G_iq) and ||S (z_k - e_g)||_inf (|S (F_k y - e_g)|, column
// maxima of |S F_k|, |S G_iq|) alike: the run keeps, per wall, the maxima over its nodes of the
// constants and (elementwise) of the weights, and
//   sup_t sigma g(t) <= C + W . |dev| + W_u . |u| + max_i (-sigma u_i)
// (the static part keeps its cancellation in C; only the chord loss, O(d^2), is taken in norms).
// The run is certified when that is < -tol for every wall, tol = 1e-9 b_j + 64 eps max |Wall|. A
// longer run's nodes include a shorter one's from the same start (the same reference), so runs
// are certified shortest first and the first refusal ends the search; a position where none is
// certified is skipped on its next 2^k - 1 visits after k refusals in a row (at most
// kMaxBackoff), as the pair's fusion backs off. Checked independently in the tests: every run
// certified along a rattling and an engine-excited trajectory steps without an event.
// Once the tables of the visited (combination, position, level) are held, Advance() allocates
// nothing.
// Held runs are re-checked at every use: the period's grid repeats only up to rounding (later
// periods' lengths drift by the absolute time's rounding, and TrainGrid's merge tolerance grows
// with 4 eps t, so a merge of two meshes' boundaries can change), so a held run is applied only
// where the walk's mesh segments are the same and its lengths within 1e-9 relative. The levels of
// a position are tried shortest first and the first failure ends the try, so when level l is
// checked level l - 1 has passed the same check on the same walk. Per position a memo
// (Entry::nested) records which levels start, bit for bit, with the previous level's segments and
// lengths (true when both were built from one walk, the usual case); for those the first half
// would compare the same values against the same bound and is skipped: only the second half is
// compared. That is exact (the same accept/refuse decision as the full check); a level built on
// another visit than the one below it keeps the full check.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

class TrainSegmentRuns {
 public:
  static constexpr int kMaxBackoff = 63;
  // max_level: runs of up to 2^max_level grid segments (>= 1); limit_bytes: the tables held;
  // max_period_segments: fusion is off when the common period has more grid segments; `cancel`
  // (TrainStepperOptions::cancel) is polled per grid segment of a run's build.
  TrainSegmentRuns(const TrainTables& tables, int max_level, size_t limit_bytes,
                   long max_period_segments, const std::atomic<bool>* cancel = nullptr);
  ~TrainSegmentRuns();
  // At the start of the grid segment at `position` of the common period (`grid` there, z the
  // state there, every mesh held in `states`): the longest certified run that ends by `end_time`
  // is applied to z and `grid` moved past it; tables not held yet are built only when `build`.
  // Returns its grid segments (0: none, nothing changed).
  long Advance(long position, const std::vector<ContactState>& states, double end_time, bool build,
               TrainGrid& grid, Eigen::VectorXd& z);
  // Forgets the refusals' back-off (a restarted run decides as a fresh one); keeps the tables.
  void ResetBackoff();
  size_t bytes() const { return bytes_; }
  long tables() const { return tables_; }      // runs built
  long refusals() const { return refusals_; }  // positions tried where no run was certified
  long period_segments() const { return period_segments_; }  // G (0: not counted yet)

 private:
  struct Wall {
    int mesh = 0;
    bool drive = true;
    double sign = 1.0;
  };
  struct Run {
    int length = 0;
    Eigen::MatrixXd product;        // P, on Pi z
    Eigen::MatrixXd inputs;         // m x (length p): column i p + q is input q set at segment i
    std::vector<int> segments;      // meshes x length: each grid segment's mesh segments
    Eigen::VectorXd lengths;        // h_i, s
    Eigen::VectorXd reference;      // y
    Eigen::VectorXd constant;       // per wall: C (the static walls' -sigma Wall included)
    Eigen::VectorXd tolerance;      // per wall: tol
    Eigen::MatrixXd weights;        // walls x m: W
    Eigen::MatrixXd input_weights;  // walls x (length p): W_u
  };
  struct Entry {
    std::vector<std::unique_ptr<Run>> levels;  // [l - 1]: the run of 2^l grid segments, or null
    int skip = 0, backoff = 0;
    uint32_t nested = 0;  // bit l: level l's run starts with level l - 1's (see the header)
  };
  struct Key {
    uint64_t states = 0;
    long position = 0;
    bool operator==(const Key& o) const { return states == o.states && position == o.position; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return std::hash<uint64_t>()(k.states * 0x9e3779b97f4a7c15ULL ^
                                   static_cast<uint64_t>(k.position));
    }
  };
  // Walks walk_ on to `count` grid segments from the run's start, recording each one's mesh
  // segments, length, inputs and wall terms; false when one would end after `end_time`.
  bool WalkTo(int count, double end_time);
  // The run of `length` grid segments from the walk's start in `states`, or null beyond the limit.
  std::unique_ptr<Run> Build(int length, const std::vector<ContactState>& states);
  bool Certify(const Run& run) const;
  // Whether `run` (2^l grid segments) starts with `shorter`'s (2^(l-1)) segments and lengths, bit
  // for bit.
  static bool Nested(const Run& shorter, const Run& run);
  void WallsOf(const std::vector<ContactState>& states);

  const TrainTables& t_;
  int max_level_;
  size_t limit_bytes_;
  long max_period_segments_;
  const std::atomic<bool>* cancel_;
  long period_segments_ = 0;
  bool enabled_ = true;
  std::unordered_map<Key, Entry, KeyHash> entries_;
  size_t bytes_ = 0;
  long tables_ = 0, refusals_ = 0;
  // Scratch of one attempt (sized once: no allocation).
  TrainGrid walk_;
  int walked_ = 0;
  std::vector<Wall> walls_;
  std::vector<int> segments_;          // meshes x 2^L
  Eigen::VectorXd lengths_;            // 2^L
  Eigen::VectorXd inputs_;             // 2^L p: u_iq at i p + q
  Eigen::VectorXd abs_inputs_;         // |u|
  Eigen::MatrixXd wall_terms_;         // walls x 2^L: -sigma u_i (the error input's wall part)
  Eigen::VectorXd slots_, dev_, end_;  // m
};

// Segment-run fusion checked against stepping, run by run (validate's row, the tests): a stepper
// on `tables` (no jumps, no fusion, event method `method`) walks grid segment by grid segment
// from z0 in states0 over `segments` grid segments; at every grid segment start its state is
// offered to a TrainSegmentRuns on `fused_tables` (default levels and limit, tables built as it
// goes) and each certified run is compared with the same grid segments stepped from the same
// state. Each run from the stepped state, not end to end: a rattle amplifies any rounding
// difference about tenfold per millisecond.
struct SegmentRunCheck {
  long runs = 0, fused = 0, refusals = 0;
  long runs_with_event = 0;  // certified runs whose stepped grid segments had an event or grazing
  long events = 0;           // of the stepped walk
  double worst_te = 0.0;     // max over runs of max_i |TE_i difference| / max_i |TE_i|, run's end
  bool stopped = false;      // the stepper stopped (summary says why); nothing after it checked
  TrainStepperSummary summary;  // the stepper's
};
SegmentRunCheck CheckSegmentRuns(const TrainTables& tables, const TrainTables& fused_tables,
                                 const Eigen::VectorXd& z0,
                                 const std::vector<ContactState>& states0, long segments,
                                 EventMethod method = EventMethod::kSpectral,
                                 const std::atomic<bool>* cancel = nullptr);

}  // namespace gearnvh
