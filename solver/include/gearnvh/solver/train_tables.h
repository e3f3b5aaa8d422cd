// Piecewise-LTI model of a gear train at tier 1 and its lazily built, bounded table cache
// (docs/design.md §11, docs/gear-trains.md).
//
// Tier 1: one torsional DOF per body (TorsionalModes), angles are perturbations from the nominal
// rotation, each in its body's own direction. Augmented state z = [x; x'; 1; q] (m = 2n + 1 + 2K),
// q the exosystem of the K engine orders, the torque sum_k d_k a_k sin(w_k t + phi_k) (w_k = k
// |W_s| for an order k of its shaft s; d_k below): per order the pair q_k = a_k [sin, cos](w_k t +
// phi_k), q_k' = w_k [[0, 1], [-1, 0]] q_k, the torque sum_k d_k q_k,sin. The inputs are carried
// exactly (no hold, no limit on the order): the generator stays LTI, gaining the eigenvalues
// +-i w_k. Mesh i couples its
// bodies through delta_i = v_i^T x, v_i = r_b,a e_a - r_b,b e_b; it has its own mesh period T_i,
// its own S_i segments (the pair's segmentation of that mesh at the torque it transmits), and per
// segment j the drive and back stiffness k+_ij, k-_ij and the unloaded error e_ij; b_i =
// backlash/2, c_i = 2 zeta_i sqrt(kbar_i m_e,i), m_e,i = J_a J_b / (J_a r_b,b^2 + J_b r_b,a^2) from
// the bodies' polar inertias. For the contact tuple sigma = (j_i, s_i)_i of a grid segment:
//   z' = A_sigma z,  A = [[0, I, 0, 0], [-M^-1 K_s, -M^-1 C_s, M^-1 f_s, M^-1 D], [0, 0, 0, W]]
// (D = [d_k, 0] per order: the excitation drives through the sine state, d_k the torque per unit
// amplitude on the shaft s it acts on, J_s e_s for an acceleration order and e_s for a torque
// order; w_k = k |W_s|, k the order of that shaft's speed; W = diag(w_k [[0, 1], [-1, 0]]))
//   K_s = sum_{i in drive} k+_ij v_i v_i^T + sum_{i in back} k-_ij v_i v_i^T,  C_s likewise with
//   c_i, f_s = f + sum_{drive} k+_ij (e_ij + b_i) v_i + sum_{back} k-_ij (e_ij - b_i) v_i,
// f the constant torques (every load resists its body, the input body is driven by the torque that
// balances them: the free rotation carries no mean torque). Gaps (rows on z): g+_i = v_i^T x - e_ij
// - b_i (drive while > 0), g-_i = v_i^T x - e_ij + b_i (back while < 0). Tooth friction (mu_i = the
// mesh's friction_coefficient > 0), as the pair (component_model.h): the normal force N = k g + c
// g' of a flank acts along u+_ij = v_i + mu_i w+_ij (drive) or u-_ij = v_back,i - mu_i w-_ij
// (back), w_ij = sigma_ij t_i + a1_ij arm_a + a2_ij arm_b the segment's friction vector
// (MeshSegment: sigma and arms per flank, the segmentation splits at the pitch point, where
// friction reverses). Tier 1: t = 0, arm_a = e_a and arm_b = -e_b (the gears' running angles; the
// pair's wheel angle about +z is -theta_b), so in contact the generator holds
//   K_s = sum k_ij u_ij v_i^T,  C_s = sum c_i u_ij v_i^T,  f_s = f + sum k_ij (e_ij +- b_i) u_ij,
// non-symmetric rank-one terms; the error column is M^-1 k_ij u_ij. Gaps stay on v_i. The free
// rotation r still has K_s r = C_s r = 0 (v_i^T r = 0), but r^T u_ij = mu r^T w_ij != 0: friction
// brakes it. The input body is driven by f_in + dT, dT = sum_i mu_i F_i <r^T w_i> / r_in, the mean
// friction loss at the static torque flow (F_i = transmitted torque / r_b,b, <.> the cycle mean
// over the loaded flank's segments): the free rotation carries no mean torque, as on the pair.
// Manufacturing errors (runout, pitch errors; model/manufacturing_errors.h): mesh i whose gears
// carry errors has its own input slot u_i = e_err,i (m), held at its mean over each grid segment
// (SetInputs), so z = [x; x'; 1; q; u_err] and m = 2n + 1 + 2K + error_inputs. The error adds to
// the unloaded error e_ij exactly as on the pair: A gains the column M^-1 k_ij v_i for u_i while
// mesh i is in contact (the force k (delta - e - u_i -+ b)), and both walls move by u_i (Wall(..,
// z)): the closed forms of delta_i are unchanged, the wall is constant over a grid segment. A gear
// that takes part in two meshes (an idler) brings its runout into both, at its own nominal angle.
//
// Time grid: mesh i is periodic in T_i with segment boundaries t_ij; the train's grid is the union
// of every mesh's boundaries, generated on the fly from integer cycle counts (no drift, no table of
// the common period: a train whose common period is long or missing costs nothing extra here).
// Boundaries of different meshes closer than kMergeTolerance * min T_i are one boundary. The
// common period (CommonPeriod: the smallest whole number of input revolutions after which every
// mesh and every excitation order is back in phase, up to a limit) is used to recentre the free
// rotation and to report; when none is found within the limit, the free rotation is recentred
// once per input revolution (exact either way: it changes no gap and no force).
//
// Tables per tuple: the generator (and a sub-step bound for the dense path) when a tuple is first
// visited; its spectral decomposition and a ClosedFormGap per mesh when it is entered for the
// decompose_after_visits-th time (a rattle impact visits most tuples once: the dense path is
// cheaper than a decomposition used for one or two pieces). Held in a cache bounded in bytes
// (TrainTableOptions) that evicts the fewest-visited, then least recently used tuples; the visit
// count of every tuple key seen survives eviction, so which path a tuple takes does not depend on
// the cache limit.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

// A contact of the train: a gear mesh, or a stage of a multi-stage coupling. A coupling's stage s
// (s >= 2, from_s, stiffness k_s) is the dead-band spring (k_s - k_s-1) sign(th) max(|th| - from_s,
// 0) on its twist th = v^T x: a mesh with unit radii, backlash 2 from_s, one segment of constant
// stiffness and no error, so its stage changes are located like impacts (docs/gear-trains.md).
struct TrainMeshTable {
  std::string name;  // "g1-g2"; a coupling's stage: "clutch stage 2"
  int body_a = 0, body_b = 0;
  int coupling = -1;  // a coupling stage's coupling (GearTrain::couplings); -1 for a gear mesh
  int stage = 0;      // a coupling stage's number (2 for the second stage); 0 for a gear mesh
  bool gear_mesh() const { return coupling < 0; }
  // A coupling stage's state at the static point: engaged on the side of its coupling's static
  // twist (TrainCouplingModel::MeanTwist, exact: a coupling carries the torque flow's share).
  ContactState static_state = ContactState::kFree;
  Eigen::VectorXd v;  // drive-flank mesh vector on the n coordinates (the TE row)
  // The back flank's gap vector: g-_i = v_back^T x - e_ij + b_i. Tier 1: v (the torsional parts
  // are equal); from tier 2 on the lateral terms of the back line of action differ.
  Eigen::VectorXd v_back;
  bool distinct_back = false;  // v_back != v
  const Eigen::VectorXd& Vector(bool drive) const { return drive ? v : v_back; }
  // The coordinates where v or v_back is nonzero, ascending (tier 1: the mesh's two bodies);
  // empty: every coordinate. The gap rows are evaluated on these only.
  std::vector<int> support;
  void FindSupport();  // from v and v_back
  // Vector(drive)^T x over the first n entries of x (on the support).
  double Dot(bool drive, const double* x) const {
    const Eigen::VectorXd& u = Vector(drive);
    if (support.empty()) return u.dot(Eigen::Map<const Eigen::VectorXd>(x, u.size()));
    double sum = 0.0;
    for (int j : support) sum += u[j] * x[j];
    return sum;
  }
  double period = 0.0;           // T_i, s
  std::vector<double> boundary;  // segment starts within [0, T_i), plus T_i (size S_i + 1), s
  std::vector<double> k_drive, k_back, error;  // per segment: N/m, N/m, m
  double half_backlash = 0.0;                  // b_i, m
  // Bound on |g+_i| and |g-_i| (m): 2 b_i plus the teeth's whole depth, past which the gears
  // would have passed through each other or out of mesh (SegmentTables::displacement_limit).
  double displacement_limit = 0.0;
  double damping = 0.0;                        // c_i, N s/m
  double effective_mass = 0.0;                 // m_e,i, kg
  double transmitted_torque = 0.0;             // N m on gear b (static torque flow)
  // Tooth friction (see the header): mu, per segment each flank's sigma and arms, and the force
  // directions u+_ij, u-_ij (SetFrictionForces); empty without friction.
  double friction = 0.0;
  std::vector<FlankSegment> drive_flank, back_flank;
  std::vector<Eigen::VectorXd> force_drive, force_back;
  bool has_friction() const { return !force_drive.empty(); }
  // The direction of the flank's force in segment j: u_ij, or Vector(drive) without friction.
  const Eigen::VectorXd& ForceVector(int segment, bool drive) const {
    if (force_drive.empty()) return Vector(drive);
    return (drive ? force_drive : force_back)[static_cast<size_t>(segment)];
  }
  // Runout and pitch errors of the mesh's two gears, at their nominal speeds in this train, and
  // the index of the mesh's error input among the error slots (-1: the gears carry none).
  MeshErrorExcitation errors;
  int error_input = -1;
  int segments() const { return static_cast<int>(error.size()); }
};

struct TrainTables {
  Tier tier = Tier::kTier1;
  int n = 0;  // coordinates: tier 1 one per body; else the reduced model's (train_reduced_tables.h)
  int m = 0;  // 2n + 1 + 2K + error inputs
  std::vector<std::string> body_names;
  std::vector<bool> loose;  // per body: a loose gear
  // Per body (rows) its angle in its own direction of rotation as a row on x (tier 1: identity).
  Eigen::MatrixXd body_angles;
  Eigen::VectorXd inertia;               // diagonal of M: J per body, kg m^2 (reduced: ones)
  Eigen::VectorXd body_inertia;          // J per body, kg m^2, at every tier
  Eigen::VectorXd force;                 // f: constant torques, N m (friction loss included)
  double friction_loss_torque = 0.0;     // dT, the mean friction loss the input supplies, N m
  // Per engine order k (excitation[k]) its direction d_k, columns of an n x K matrix: the torque
  // per unit of its amplitude on the shaft it acts on (tier 1: J_s e_s for an acceleration order,
  // e_s for a torque order; a reduced tier: B^T of that).
  Eigen::MatrixXd excitation_directions;
  // From tier 2 on, the structure's bearings (TrainStructure::bearings) and the rows on z of each
  // one's force on the housing, rows 3b, 3b + 1, 3b + 2 for x, y, z: diag(k_r, k_r, k_a) u + c u'
  // at its point (BearingPointRows). None at tier 1, which has no lateral DOF.
  std::vector<StructureBearing> bearings;
  Eigen::MatrixXd bearing_force_rows;
  // Structural K_0 and C_0 (+ input speed x gyroscopic G) of a reduced tier, added to every
  // tuple's mesh terms. At tier 1 K_0 is the couplings' sum k_j w_j w_j^T (w_j = e_a - e_b) and C_0
  // theirs with c_j plus the loads' viscous drag sum c w w^T (LoadAction); each is empty without
  // a term.
  Eigen::MatrixXd structural_stiffness, structural_damping;
  double input_speed = 0.0;  // rad/s
  // The engine orders, each as an order of the input shaft's speed (ExcitationOrderOfInput:
  // k |W_s| / W_in) with its amplitude as written (rad/s^2 or N m) and phase; orders at one
  // frequency on one shaft summed (DistinctOrders).
  std::vector<ExcitationOrder> excitation;
  // The contacts: the gear meshes in file order (TrainSpec::meshes), then the couplings' stages
  // after their first (coupling by coupling, stage by stage).
  std::vector<TrainMeshTable> meshes;
  // The gear meshes, meshes[0, gear_meshes): what per-mesh results list.
  int gear_meshes = 0;
  // The free rotation r (th_j ~ |w_j|, M-normalised; K_s r = 0 and v_i^T r = 0 for every tuple)
  // and the row r^T M that measures it.
  Eigen::VectorXd rigid_rotation;
  Eigen::RowVectorXd recenter_row;
  // The rotation of each fixed shaft (columns, M-normalised and M-orthogonal to r and to each
  // other): neutral like r (nothing reaches it), but not moved at all; empty without fixed shafts.
  Eigen::MatrixXd standing_rotations;
  // Whether a viscous drag damps r (C_0 r != 0): r's speed then decays, and only its angle is
  // neutral (DragDampsFreeRotation).
  bool free_rotation_damped = false;
  // The neutral directions of the elastic state [x; x'] as columns, orthonormal in diag(M, M):
  // r's position, its velocity unless free_rotation_damped, and each standing rotation's position
  // and velocity.
  Eigen::MatrixXd NeutralBasis() const;
  int neutral_directions() const {
    return (free_rotation_damped ? 1 : 2) + 2 * static_cast<int>(standing_rotations.cols());
  }
  double common_period = 0.0;    // s; 0 when none within the limit
  double longest_segment = 0.0;  // the longest segment of any mesh, s (bounds every grid segment)

  int bodies() const { return static_cast<int>(body_names.size()); }
  int constant_slot() const { return 2 * n; }
  // The wall of gap g+ (drive) or g- of mesh i in segment j: g = delta_i - Wall; and g at z.
  double Wall(int mesh, int segment, bool drive) const;
  double GapValue(int mesh, int segment, bool drive, const Eigen::VectorXd& z) const;
  // The rounding floor of that gap at z: 1e-12 b_i + 64 eps (sum_j |v_ij x_j| + |wall|).
  double GapTolerance(int mesh, int segment, bool drive, const Eigen::VectorXd& z) const;
  // The first of the input slots (the orders' states, then the error inputs): the slots SetInputs
  // sets at a grid segment's start.
  int input_slot() const { return 2 * n + 1; }
  // The sine state of excitation order k (its cosine state follows).
  int ExcitationSlot(int order) const { return 2 * n + 1 + 2 * order; }
  int excitation_states() const { return 2 * static_cast<int>(excitation.size()); }
  // Manufacturing errors (train_errors.cc): meshes with an error input, each its slot.
  int error_inputs = 0;
  int ErrorSlot(int mesh) const;  // 2n + 1 + 2K + k for the k-th error input, -1 without errors
  // u_i, the error input of `mesh` in z (0 without errors), m.
  double ErrorInput(int mesh, const Eigen::Ref<const Eigen::VectorXd>& z) const;
  // The wall with the error input of z: Wall(mesh, segment, drive) z_c + u_i.
  double Wall(int mesh, int segment, bool drive, const Eigen::Ref<const Eigen::VectorXd>& z) const;
  // Sets the input slots of z for the grid segment [start, start + h], which lies in segment
  // segments[i] of cycle cycles[i] of every mesh i, z being at `start`: the orders' states there
  // (SetExcitation) and each mesh's error mean (the pitch part is constant per mesh segment, the
  // runout's mean in closed form). Allocation-free.
  void SetInputs(const std::vector<long>& cycles, const std::vector<int>& segments, double start,
                 double h, Eigen::Ref<Eigen::VectorXd> z) const;
  // The orders' states q_k at time t (exact, times the constant slot z_c = 1).
  void SetExcitation(double t, Eigen::Ref<Eigen::VectorXd> z) const;
  // Adds the orders' columns M^-1 d on the sine states and the exosystem W to a generator.
  void AddExcitationColumns(Eigen::Ref<Eigen::MatrixXd> A) const;
  // Adds the error inputs' columns M^-1 k_ij v_i of the meshes in contact to a generator.
  void AddErrorColumns(const std::vector<int>& segments, const std::vector<ContactState>& states,
                       Eigen::Ref<Eigen::MatrixXd> A) const;
  // Adds the orders' acceleration M^-1 sum_k d_k a_k sin(w_k t + phi_k) on the n coordinates at
  // time t (no allocation: the CVODE reference calls it per right-hand side); and their largest
  // frequency max_k w_k (0 without orders), rad/s.
  void AddExcitationAcceleration(double t, Eigen::Ref<Eigen::VectorXd> acceleration) const;
  double HighestExcitationFrequency() const;
  double InputRevolution() const;  // 2 pi / input speed, s
};

// Options of the table build and of the cache.
struct TrainTableOptions {
  // Upper bound of the cached tables' bytes; beyond it the fewest-visited tuples (of equal visits
  // the least recently used) are evicted, down to 7/8 of it (at least the tuple in use is always
  // kept). >= 1.
  size_t cache_limit_bytes = size_t{160} << 20;
  // A tuple is decomposed (V3 closed forms) when it is entered for this many times (consecutive
  // pieces on one tuple are one entry); before that it takes the dense path. 1: at the first
  // entry. >= 1.
  int decompose_after_visits = 3;
  // Decompositions with |S|_1 |S^-1|_1 above this use the dense (Taylor) path for that tuple.
  double max_condition = 1e6;  // >= 1
  // The common period is searched up to this many input revolutions. >= 1.
  long max_common_period_revolutions = 1000;
  // Polled per mesh and between the reduction's steps while the tables are built (RunCancelled
  // once set; SolverOptions::cancel). Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;
};

// Builds the tier-1 train model (fixed per train): per mesh segmentation, loads, damping.
// `segments_per_cycle` as analysis.segments_per_cycle; `damping_ratio` per mesh from the spec.
TrainTables BuildTrainTables(const TrainSpec& spec, const GearTrain& train,
                             const TrainTableOptions& options = {});
// The generalised directions of a mesh's friction on the solver's coordinates: each flank's
// sliding translation (t at gear a, -t at gear b; zero at tier 1) and a unit arm on each gear's
// rotation in the pair's sense (tier 1: e_a and -e_b).
struct FrictionBasis {
  Eigen::VectorXd slide_drive, slide_back, arm_a, arm_b;
};
// Sets mt.force_drive/back from its flanks' segments and the basis (nothing without friction).
void SetFrictionForces(TrainMeshTable& mt, const FrictionBasis& basis);
// dT (see the header) on the free rotation r (running angles, tier 1), input body `input`:
// `back_loaded[i]` when mesh i transmits its torque on the back flank.
double FrictionLossTorque(const TrainTables& t, const std::vector<bool>& back_loaded, int input);
// Numbers the error inputs of the meshes whose errors are active and sets m = 2n + 1 + 2K + that
// count (the tier-1 build and the reduced tiers, whose n differs, call it).
void AssignErrorInputs(TrainTables& tables);

// Tables of one contact tuple. The generator depends on the segment of a mesh only while that
// mesh is in contact, so a free mesh's segment is left out of the key. The gaps g+_i and g-_i
// differ from delta_i = v_i^T x only by the constant wall e_ij +- b_i, so one closed form of
// delta_i per mesh serves both walls in every segment (ClosedFormGap::Load(w, constant)).
struct TrainSystem {
  Eigen::MatrixXd A;  // generator, m x m
  SpectralDecomposition decomposition;
  bool decomposed = false;  // the decomposition was attempted (TrainTableOptions)
  bool spectral = false;    // decomposition usable (else the dense Taylor path)
  // Dense path: sub-step length, min(1/2 / rho, kMaxDenseStepNorm / rate): rho(A) substep <= 1/2,
  // and rate * substep <= kMaxDenseStepNorm bounds the Taylor remainder (taylor_root::Tail)
  // whatever A's non-normality.
  double substep = 0.0;
  // The bound on A's spectral radius (BoundTupleRate, train_rate_bound.h: the Rayleigh quotients of
  // the pencil lambda^2 M + lambda C + K, friction's and skew damping's terms bounded apart), 1/s.
  double rho = 0.0;
  // sqrt(lambda_max(M^-1 K_sym)), K_sym without friction's rank-one terms (a scale, not a bound):
  // the decomposition's velocity balance, rad/s.
  double w_ref = 1.0;
  // The columns c < 2n of A with a nonzero acceleration entry (the positions and velocities of
  // the bodies a contact or the structure couples), ascending: the dense path's Taylor products
  // skip the others, which are zero (a loose gear whose mesh is free is a free body).
  std::vector<int> coupled_columns;
  Eigen::VectorXd balance;  // S = BalancingScale(A, n, w_ref)
  double rate = 0.0;        // ||S A S^-1||_inf (ScaledRowNorm), 1/s
  static constexpr double kMaxDenseStepNorm = 1.5;
  // Per mesh, the closed form of delta_i (spectral only); mutable: Load() keeps its coefficients.
  mutable std::vector<ClosedFormGap> delta;
  // Per mesh, the closed form of v_back^T x when some mesh's back vector differs (else empty).
  mutable std::vector<ClosedFormGap> delta_back;
  // The closed form whose constant gives the drive (g+) or back (g-) gap of `mesh`.
  ClosedFormGap& Gap(size_t mesh, bool drive) const {
    return !drive && !delta_back.empty() ? delta_back[mesh] : delta[mesh];
  }
  size_t bytes = 0;
};

// The key of a tuple: per mesh segment * 3 + state (a free mesh: segment 0), 16 bits per mesh.
using TupleKey = std::vector<uint64_t>;

struct TrainCacheSummary {
  long hits = 0, misses = 0, evictions = 0;
  long ill_conditioned = 0;  // decompositions that failed (those tuples keep the dense path)
  long decompositions = 0;   // decompositions attempted
  size_t bytes = 0, peak_bytes = 0;  // tuples held (bounded by cache_limit_bytes)
  // The index of every tuple key seen with its entry count (never evicted, an open-addressing
  // table at most 3/4 full: 24 + 8 * key words bytes per slot; not part of `bytes`).
  size_t index_bytes = 0;
  long tuples = 0;  // held now
};

// Bounded cache of TrainSystems (fewest visits, then least recently used, evicted first). Get() on
// a held tuple does not allocate.
class TrainSystemCache {
 public:
  TrainSystemCache(const TrainTables& tables, const TrainTableOptions& options);
  // segments[i], states[i] per mesh; `key` is scratch of KeyWords() words (filled here).
  const TrainSystem& Get(const std::vector<int>& segments, const std::vector<ContactState>& states,
                         TupleKey& key);
  int KeyWords() const { return key_words_; }
  const TrainCacheSummary& summary() const { return summary_; }

 private:
  TrainSystem Build(const std::vector<int>& segments,
                    const std::vector<ContactState>& states) const;
  // DampingRateBound (train_rate_bound.h) of the tuple's damping C: it depends on the contact
  // states only (c_i is constant per mesh), so it is computed once per state combination (2 bits
  // per mesh; trains of more than 32 meshes compute it per tuple).
  double DampingRate(const std::vector<ContactState>& states, const Eigen::MatrixXd& C) const;
  void Decompose(TrainSystem& s) const;
  static constexpr size_t kNone = ~size_t{0};
  struct Slot {
    size_t entry = kNone;  // its entry in entries_ while held
    long visits = 0;
    bool used = false;  // a key is stored here
    bool held = false;  // its tables are in the cache (false once evicted: the visit count stays)
  };
  struct Entry {
    TrainSystem system;
    size_t slot = 0;    // its index slot (updated when the index grows); the key is stored there
    uint64_t used = 0;  // the tick of its last Get: the least recent is evicted first
    bool held = false;  // false: free for the next tuple built
  };
  // The index slot of `key`: where it is stored, else the empty slot where it belongs.
  size_t Probe(const uint64_t* key) const;
  // Doubles the index and re-inserts every key (only when a new key is stored).
  void GrowIndex();
  size_t IndexBytes() const;
  // Counts an entry of `e`'s tuple, decomposes it when due, evicts beyond the limit.
  const TrainSystem& Enter(Entry& e);
  // Beyond the limit: the fewest-visited, then least recently used tuples go (one scan and sort
  // of the held visit counts and ticks),
  // down to 7/8 of the limit so that the next tuples built do not each scan again. Which tuples
  // are held changes no result (the visit counts survive, a rebuilt tuple is the same).
  void Evict();
  void EvictOldest();
  const TrainTables& t_;
  TrainTableOptions options_;
  int key_words_ = 1;
  // The held tuples (a deque: their addresses stay while others are added); an evicted entry's
  // place is reused (free_entries_). No list to splice on every Get: each entry keeps the tick of
  // its last use.
  std::deque<Entry> entries_;
  std::vector<size_t> free_entries_;
  size_t recent_ = kNone;  // the entry of the last Get (consecutive pieces mostly stay on it)
  uint64_t tick_ = 0;
  std::vector<std::pair<uint64_t, size_t>> eviction_order_;  // Evict()'s scratch
  // The index of every tuple key seen: open addressing with linear probing, at most 3/4 full,
  // the keys inline (index_keys_[slot * key_words_ ...]) so a lookup touches two arrays and no
  // per-key heap block.
  std::vector<uint64_t> index_keys_;
  std::vector<Slot> index_;
  size_t index_used_ = 0;
  int index_bits_ = 0;                                         // index_.size() == 2^index_bits_
  mutable std::unordered_map<uint64_t, double> damping_rate_;  // per state combination
  TrainCacheSummary summary_;
};

}  // namespace gearnvh
