// V3, the default EventLocator (event_locator.h): closed-form event location in the decoupled
// coordinates of each segment's generator (spectral_gap.h).
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <vector>

#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

// V3: per whole segment, w = S^-1 z (one matvec); the gap of every wall is the closed form
// p(t) + sum e^{sigma t}(alpha cos wt + beta sin wt) + sum gamma e^{lambda t} (ClosedFormGap);
// its first rise is found with certified bounds and Newton. A segment start is first screened
// (ClosedFormGap::ClearOfWall: a few dot products with rows precomputed per segment, state and
// wall); a wall it clears is not searched, so most segments skip Load() and the search (and a
// segment with an event searches only the walls the screen did not clear), and
// the result is the same (the screen is sufficient and keeps the search's rounding margin).
// A start entered with z valid is checked for the time-triggered switch on z only where the
// screen does not clear every wall (a cleared wall has sign g(0) <= -floor on w = S^-1 z).
// At an event z <- S e^{B t*} w and the
// search restarts in the new state; after the last event of a segment z <- S e^{B(h - t)} w.
// A segment without an event is left in one matvec:
//   carried (state.allow_carry, the next segment's decomposition in the same state usable and
//     the carry's error bound within SolverOptions::carry_max_error): w_{j+1} = C_j w with
//     C_j = S_{j+1}^-1 Pi S_j e^{D_j h_j} (Pi clears the input slots), and the next segment adds
//     u_q S_{j+1}^-1 e_q for its inputs: the S^-1 z of the next segment is saved, z is stale
//     (LocatorState::z_stale) until Materialise(). The last segment of a cycle writes
//     z = S_j e^{D_j h_j} w (the same matrix without S_{j+1}^-1 Pi), so z is valid at every
//     cycle end. The closed-form gap at the start decides the time-triggered switch; a start
//     within half the wall tolerance of a wall materialises z and takes the dense path.
//   otherwise: z <- Phi z (the dense propagator) when the segment was entered with z valid.
// An ill-conditioned (segment, state) (cond(S) > spectral_max_condition) is handed to the Taylor
// search for the rest of the segment. Decompositions and carry matrices are built when their
// (segment, state) is first visited (a loaded run never decomposes its free and back states), so
// DoStep allocates only on a first visit.
class SpectralLocator final : public EventLocator {
 public:
  static constexpr EventMethod kMethod = EventMethod::kSpectral;
  static constexpr int kLineDoubles = 8;  // a padded column's unit: one 64-byte line
  SpectralLocator(const SegmentTables& tables, const SolverOptions& options);
  EventMethod method() const override { return kMethod; }
  bool DoStep(int segment, double start, LocatorState& state, EventHandler& handler) override;
  void Materialise(LocatorState& state) override;
  // Entered carried (state.z_stale) at `segment` of mesh cycle `cycle`: sets each segment's inputs
  // (SegmentTables::SetInputs with the cycle's phases) and carries the state through every
  // segment the screen clears, as DoStep would, without a call per segment. Returns the first
  // segment not settled (its inputs set, state still carried) or segments() when the cycle's
  // last segment was carried out (z written). No event can happen in the segments it settles.
  int CarryThrough(int segment, long cycle, SegmentTables::CyclePhase& phase, LocatorState& state);

 private:
  struct FreeAligned {
    void operator()(double* p) const;
  };
  struct System {
    SpectralDecomposition decomposition;
    std::array<ClosedFormGap, kGapRows> gaps;  // indexed by GapWall::gap
    bool built = false;
    bool ok = false;
    // Its carried-segment block in blocks_ (filled by Build) and its active walls.
    double* block = nullptr;
    int walls = 0;
    // Per active wall the closed form's curved-test rows (ClosedFormGap::CurvedScreenRow, the value
    // and rate rows times the wall's sign) in curved_, padded as the block's columns.
    double* curved = nullptr;
    // Whether the block holds the carry matrix: C_j (to the next segment) or S_j e^{D_j h_j}
    // (last segment of the cycle). carry_built: decided on first use.
    bool carries = false;
    bool carry_built = false;
    // Its dense matrices S, S^-1 and the segment's propagator Phi (filled by Build when ok), each
    // padded_ rows by m columns, the pad rows 0: Eigen's product over rows past the last whole
    // vector makes extra passes over the columns (at m = 46 about twice the time of 48 rows).
    std::unique_ptr<double[], FreeAligned> dense;
  };
  enum class Dense { kS = 0, kSInverse = 1, kPropagator = 2 };
  static constexpr int kDenseMatrices = 3;
  const double* DenseMatrix(const System& sp, Dense which) const {
    return sp.dense.get() + static_cast<size_t>(which) * dense_doubles_;
  }
  // y = the top y.size() rows of a dense matrix (DenseMatrix) times x (m entries).
  void MultiplyDense(const double* a, const double* x, Eigen::Ref<Eigen::VectorXd> y);
  // The system of (segment, state), decomposed on first use (inline: called on every segment).
  System& Prepared(int segment, ContactState state) {
    System& sp = systems_[segment][static_cast<int>(state)];
    return sp.built ? sp : Build(segment, state);
  }
  System& Build(int segment, ContactState state);
  // The carry matrix of (segment, state) in its block (padded_ rows, m columns), built on first
  // use; nullptr when it does not carry.
  const double* Carry(int segment, ContactState state) {
    const System& sp = systems_[segment][static_cast<int>(state)];
    if (sp.carry_built) return sp.carries ? CarryData(sp) : nullptr;
    return BuildCarry(segment, state);
  }
  const double* BuildCarry(int segment, ContactState state);
  double* CarryData(const System& sp) const {
    return sp.block + static_cast<size_t>(t_.inputs + 2 * sp.walls) * padded_;
  }
  // carried_ = C w (a carry matrix from Carry(), w of length m): padded_ entries, the pads 0.
  void CarryProduct(const double* carry, const double* w);
  // The carried path's padded vectors: at tier 1 (m known at compile time and at most one line)
  // fixed-size values, kept in registers across a run of carried segments (through the buffers,
  // every segment waited twice for a store to be forwarded to a load); otherwise maps of the
  // buffers (entry_, carried_).
  // The alignment of the buffers entry_ and carried_: what Eigen's own allocation of a VectorXd
  // guarantees (64 bytes in an AVX-512 build, 16 in a build for plain x86-64).
  static constexpr int kBufferAlignment = Eigen::AlignedMax;
  template <int M>
  using CarriedVector =
      std::conditional_t<M == Eigen::Dynamic, Eigen::Map<Eigen::VectorXd, kBufferAlignment>,
                         Eigen::Matrix<double, kLineDoubles, 1>>;
  // A buffer (entry_ or carried_) as a CarriedVector: a copy at tier 1, a map otherwise.
  template <int M>
  CarriedVector<M> CarriedView(Eigen::VectorXd& buffer) const;
  // Writes a copy back to its buffer (nothing for a map).
  template <int M>
  static void WriteBack(const CarriedVector<M>& v, Eigen::VectorXd& buffer);
  // The entry state's vector: uninitialised at tier 1, the map of entry_ otherwise.
  template <int M>
  CarriedVector<M> EntryVector() {
    if constexpr (M == Eigen::Dynamic)
      return CarriedView<M>(entry_);
    else
      return {};
  }
  // The start of a segment entered carried (state.z_stale): w = carried + sum_q u_q S_j^-1 e_q,
  // the screen of every active wall and, when every wall is clear and (segment, state) carries,
  // the carry itself (w_{j+1} = C_j w, or z at the cycle end): the whole work of ~31 of 32
  // segments of a strong-rattle cycle, all of it read from the pair's block. kClear / kNearWall:
  // not settled, w_ holds the entry state, the screen's verdict is returned and the walls it
  // cleared are kept (entered_clear_walls_). M is the state
  // dimension when it is known at compile time and fits one padded column (tier 1: m = 6, or 7
  // with manufacturing errors; every column one 8-double vector, so the carry is m vector FMAs),
  // otherwise Eigen::Dynamic; EnterCarried() picks the instance (a branch on m that never changes
  // during a run).
  enum class Entry { kSettled, kClear, kNearWall };
  // The walls the screen clears for the whole segment from w (padded; bit i: active wall i):
  // ClosedFormGap::ClearOfWall on the copies of its rows in the block and in curved_.
  // ClearWalls: from w = entry_.
  template <int M, class Vector>
  unsigned ClearWallsOf(const System& sp, int segment, const Vector& w) const;
  unsigned ClearWalls(const System& sp, int segment) const;
  // `carried`: the carried state (C_{j-1} w_{j-1}); a settled segment replaces it with its carry.
  template <int M>
  Entry EnterCarriedSized(int segment, LocatorState& state, CarriedVector<M>& carried);
  // z = carried after the cycle's last segment was carried (its carry gives z, not w).
  template <int M>
  void EndCarriedCycle(const CarriedVector<M>& carried, LocatorState& state);
  // One segment from carried_ (DoStep's entry).
  template <int M>
  Entry EnterCarriedOnce(int segment, LocatorState& state);
  Entry EnterCarried(int segment, LocatorState& state);
  template <int M>
  int CarryThroughSized(int segment, long cycle, SegmentTables::CyclePhase& phase,
                        LocatorState& state);
  double max_condition_;
  // Largest first-order relative state error a carried step may add; pairs above it step through
  // z and Phi.
  double max_carry_error_;
  std::vector<std::array<System, 3>> systems_;  // [segment][state]
  // The carried-segment blocks, one per (state, segment) in that order (a cycle in one state reads
  // consecutive blocks), each 64-byte aligned, holding what a carried segment reads in the order
  // it reads it: the input columns of S^-1, per active wall the screen's start row times the
  // wall's sign and its reach row (ClosedFormGap::ClearOfWall's linear test), then the carry
  // matrix by columns. Every column is padded with zeros to padded_ = m rounded up to 8 doubles
  // (one AVX-512 register at tier 1). Allocated once, filled when a pair is first visited.
  int padded_ = 0;
  size_t block_doubles_ = 0, curved_doubles_ = 0;
  std::unique_ptr<double[], FreeAligned> blocks_, curved_;
  size_t dense_doubles_ = 0;   // one of System::dense's matrices
  Eigen::VectorXd product_;    // MultiplyDense's padded product
  Eigen::VectorXd entry_;      // w of a carried entry, padded_ entries
  std::vector<double> w_ref_;  // per segment; 0 until its first visit
  TaylorLocator fallback_;
  Eigen::VectorXd w_, wt_, scratch_, z1_;
  // The carried state: decoupled coordinates of (carry_segment_, carry_state_) at its start,
  // input slots cleared; padded_ entries, the pads 0. Meaningful while state.z_stale (after a
  // cycle's last segment carry_segment_ is segments() and z holds the state).
  Eigen::VectorXd carried_;
  int carry_segment_ = -1;
  ContactState carry_state_ = ContactState::kFree;
  // The segment CarryThrough stopped at (-1: none); w_ holds its entry state and the stepper's next
  // call is DoStep on it, which takes w_ and the screen's verdict instead of entering again.
  int entered_segment_ = -1;
  // The last carried entry's verdict: bit i set when active wall i is clear for the whole segment.
  unsigned entered_clear_walls_ = 0;
};

}  // namespace gearnvh
