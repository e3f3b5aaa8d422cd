#include "gearnvh/solver/train_tables.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {
namespace {

constexpr int kBitsPerMesh = 16;
constexpr int kMeshesPerWord = 64 / kBitsPerMesh;
constexpr int kInitialIndexBits = 10;

size_t HashWords(const uint64_t* words, size_t count) {
  size_t h = 0x9e3779b97f4a7c15ull;
  for (size_t i = 0; i < count; ++i)
    h ^= std::hash<uint64_t>()(words[i]) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  return h;
}

}  // namespace

void TrainTableOptions::Validate() const {
  if (cache_limit_bytes < 1) {
    throw InputError("TrainTableOptions.cache_limit_bytes", 0, std::to_string(cache_limit_bytes),
                     "must be >= 1");
  }
  if (!(max_condition >= 1.0)) {
    throw InputError("TrainTableOptions.max_condition", 0, std::to_string(max_condition),
                     "must be >= 1");
  }
  if (decompose_after_visits < 1) {
    throw InputError("TrainTableOptions.decompose_after_visits", 0,
                     std::to_string(decompose_after_visits), "must be >= 1");
  }
  if (max_common_period_revolutions < 1) {
    throw InputError("TrainTableOptions.max_common_period_revolutions", 0,
                     std::to_string(max_common_period_revolutions), "must be >= 1");
  }
}

void TrainMeshTable::FindSupport() {
  support.clear();
  for (int j = 0; j < v.size(); ++j) {
    if (v[j] != 0.0 || v_back[j] != 0.0) support.push_back(j);
  }
  if (support.size() == static_cast<size_t>(v.size())) support.clear();  // dense
}

double TrainTables::Wall(int mesh, int segment, bool drive) const {
  const TrainMeshTable& mt = meshes[static_cast<size_t>(mesh)];
  const double e = mt.error[static_cast<size_t>(segment)];
  return drive ? e + mt.half_backlash : e - mt.half_backlash;
}

Eigen::MatrixXd TrainTables::NeutralBasis() const {
  const Eigen::Index s = standing_rotations.cols();
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(2 * n, neutral_directions());
  Eigen::Index c = 0;
  U.col(c++).head(n) = rigid_rotation;
  if (!free_rotation_damped) U.col(c++).tail(n) = rigid_rotation;
  U.block(0, c, n, s) = standing_rotations;  // fixed shafts: neutral, never moved
  U.block(n, c + s, n, s) = standing_rotations;
  return U;
}

double TrainTables::GapValue(int mesh, int segment, bool drive, const Eigen::VectorXd& z) const {
  const TrainMeshTable& mt = meshes[static_cast<size_t>(mesh)];
  const double e = mt.error[static_cast<size_t>(segment)];
  return mt.Dot(drive, z.data()) - e - ErrorInput(mesh, z) +
         (drive ? -mt.half_backlash : mt.half_backlash);
}

double TrainTables::GapTolerance(int mesh, int segment, bool drive,
                                 const Eigen::VectorXd& z) const {
  const TrainMeshTable& mt = meshes[static_cast<size_t>(mesh)];
  const double e = mt.error[static_cast<size_t>(segment)];
  double magnitude =
      std::abs(e + (drive ? mt.half_backlash : -mt.half_backlash) + ErrorInput(mesh, z));
  const Eigen::VectorXd& v = mt.Vector(drive);
  if (mt.support.empty()) {
    for (int j = 0; j < n; ++j) magnitude += std::abs(v[j] * z[j]);
  } else {
    for (int j : mt.support) magnitude += std::abs(v[j] * z[j]);
  }
  return 1e-12 * mt.half_backlash + 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

double TrainTables::InputRevolution() const { return 2.0 * std::numbers::pi / input_speed; }

namespace {

// Smallest whole number L of input revolutions after which every mesh (L z_a |w_a| / w_in mesh
// cycles) and every excitation order (L * order periods) is whole; 0 when none up to `limit`.
// "Whole" to the rounding of the speed ratios (products and quotients of tooth counts, a few
// roundings each): 64 eps relative. A looser test took 277 revolutions of a train of large
// coprime tooth counts for its period, with a mesh 0.0015 cycles out of phase there.
long CommonPeriodRevolutions(const std::vector<double>& cycles_per_revolution, long limit) {
  constexpr double kWhole = 64.0 * std::numeric_limits<double>::epsilon();
  for (long l = 1; l <= limit; ++l) {
    bool whole = true;
    for (double c : cycles_per_revolution) {
      const double x = static_cast<double>(l) * c;
      if (std::abs(x - std::round(x)) > kWhole * std::max(1.0, x)) {
        whole = false;
        break;
      }
    }
    if (whole) return l;
  }
  return 0;
}

// The engine orders: each as an order of the input shaft's speed, on its shaft by name (like orders
// on one shaft summed), and its direction, the torque per unit amplitude on that shaft (t.inertia
// set).
void SetExcitationOrders(const TrainSpec& spec, const TrainTopology& topo, TrainTables& t) {
  const int n = t.n;
  std::vector<ExcitationOrder> of_input = spec.operating.excitation;
  for (size_t i = 0; i < of_input.size(); ++i) {
    of_input[i].order = ExcitationOrderOfInput(spec, topo, i);
    of_input[i].on = topo.bodies[static_cast<size_t>(ExcitationBody(spec, topo, i))].name;
  }
  t.excitation = DistinctOrders(of_input);
  t.excitation_directions =
      Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(t.excitation.size()));
  for (size_t k = 0; k < t.excitation.size(); ++k) {
    const ExcitationOrder& e = t.excitation[k];
    const int body = spec.ShaftIndex(e.on);  // a shaft's body is its index
    t.excitation_directions(body, static_cast<Eigen::Index>(k)) =
        e.kind == ExcitationKind::kAcceleration ? t.inertia[body] : 1.0;
  }
}

// Couplings: k w w^T and c w w^T on their shafts' angles (one direction of rotation: w = e_a -
// e_b). They leave the free rotation alone (w^T r = 0: equal speeds).
void AddCouplings(const GearTrain& train, TrainTables& t) {
  const int n = t.n;
  for (const TrainCouplingModel& c : train.couplings) {
    if (t.structural_stiffness.size() == 0) t.structural_stiffness = Eigen::MatrixXd::Zero(n, n);
    if (t.structural_damping.size() == 0) t.structural_damping = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
    w[c.body_a] = 1.0;
    w[c.body_b] = -1.0;
    t.structural_stiffness += c.stiffness * w * w.transpose();
    t.structural_damping += c.damping * w * w.transpose();
  }
}

// The couplings' stages after their first as contacts (TrainMeshTable), after the gear meshes. The
// stage tables are constant, so their period is the train's common period (or the first mesh's
// period without one): their boundaries fall on the meshes' and restart no piece.
void AddCouplingStages(const GearTrain& train, TrainTables& t) {
  const int n = t.n;
  const double period = t.common_period > 0.0 ? t.common_period : t.meshes.front().period;
  for (size_t c = 0; c < train.couplings.size(); ++c) {
    const TrainCouplingModel& coupling = train.couplings[c];
    double below = coupling.stiffness;
    for (size_t s = 0; s < coupling.stages.size(); ++s) {
      const TrainCouplingStage& stage = coupling.stages[s];
      TrainMeshTable mt;
      mt.stage = static_cast<int>(s) + 2;
      mt.name = coupling.name + " stage " + std::to_string(mt.stage);
      mt.coupling = static_cast<int>(c);
      mt.body_a = coupling.body_a;
      mt.body_b = coupling.body_b;
      mt.v = Eigen::VectorXd::Zero(n);
      mt.v[coupling.body_a] = 1.0;
      mt.v[coupling.body_b] = -1.0;
      mt.v_back = mt.v;
      mt.FindSupport();
      mt.period = period;
      mt.boundary = {0.0, period};
      mt.k_drive = mt.k_back = {stage.stiffness - below};
      mt.error = {0.0};
      mt.drive_flank = mt.back_flank = {FlankSegment{}};
      mt.half_backlash = stage.from;
      // A twist past half a turn is no spring's: the run has left the model.
      mt.displacement_limit = std::numbers::pi;
      const double twist = coupling.MeanTwist();
      mt.static_state = twist > stage.from    ? ContactState::kDrive
                        : twist < -stage.from ? ContactState::kBack
                                              : ContactState::kFree;
      t.meshes.push_back(std::move(mt));
      below = stage.stiffness;
    }
  }
}

}  // namespace

TrainTables BuildTrainTables(const TrainSpec& spec, const GearTrain& train,
                             const TrainTableOptions& options) {
  options.Validate();
  const TrainTopology& topo = train.topology;
  TrainTables t;
  t.n = static_cast<int>(topo.bodies.size());
  const int n = t.n;
  t.inertia = Eigen::Map<const Eigen::VectorXd>(train.body_inertia.data(), n);
  t.body_inertia = t.inertia;
  t.input_speed = spec.operating.speed;
  SetExcitationOrders(spec, topo, t);
  for (const TrainBody& b : topo.bodies) {
    t.body_names.push_back(b.name);
    t.loose.push_back(b.kind == BodyKind::kLooseGear);
  }
  t.body_angles = Eigen::MatrixXd::Identity(n, n);
  t.force = Eigen::VectorXd::Zero(n);
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    const LoadAction action = ActionOfLoad(spec, topo, i);
    Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
    for (const LoadAction::Term& term : action.terms) {
      t.force[term.body] -= term.resisting;
      w[term.body] = term.direction;
    }
    if (action.viscous > 0.0) {
      if (t.structural_damping.size() == 0) t.structural_damping = Eigen::MatrixXd::Zero(n, n);
      t.structural_damping += action.viscous * w * w.transpose();
    }
    t.free_rotation_damped = t.free_rotation_damped || action.DampsFreeRotation();
  }
  AddCouplings(train, t);
  t.force[topo.input_body] += train.input_torque;

  Eigen::VectorXd rigid(n);
  for (int b = 0; b < n; ++b) rigid[b] = std::abs(topo.bodies[static_cast<size_t>(b)].speed);
  rigid /= std::sqrt(rigid.dot(t.inertia.cwiseProduct(rigid)));
  t.rigid_rotation = rigid;
  t.recenter_row = t.inertia.cwiseProduct(rigid).transpose();
  t.standing_rotations = Eigen::MatrixXd::Zero(n, 0);
  for (int b = 0; b < n; ++b) {
    if (topo.bodies[static_cast<size_t>(b)].speed != 0.0) continue;  // a fixed shaft stands
    t.standing_rotations.conservativeResize(n, t.standing_rotations.cols() + 1);
    t.standing_rotations.rightCols(1) = Eigen::VectorXd::Unit(n, b) / std::sqrt(t.inertia[b]);
  }

  std::vector<double> cycles_per_revolution;
  std::vector<bool> back_loaded;
  for (const ExcitationOrder& e : t.excitation) cycles_per_revolution.push_back(e.order);
  for (size_t i = 0; i < train.meshes.size(); ++i) {
    ThrowIfCancelled(options.cancel);
    const TrainMeshModel& mm = train.meshes[i];
    TrainMeshTable mt;
    mt.name = mm.name;
    mt.body_a = mm.body_a;
    mt.body_b = mm.body_b;
    const double ra = mm.geometry.pinion.base, rb = mm.geometry.wheel.base;
    mt.v = Eigen::VectorXd::Zero(n);
    mt.v[mm.body_a] += ra;
    mt.v[mm.body_b] -= rb;
    mt.v_back = mt.v;
    mt.FindSupport();
    const int teeth = spec.gears[static_cast<size_t>(mm.gear_a)].gear.teeth;
    const double speed_a = std::abs(topo.bodies[static_cast<size_t>(mm.body_a)].speed);
    mt.period = 2.0 * std::numbers::pi / (teeth * speed_a);
    cycles_per_revolution.push_back(teeth * speed_a / t.input_speed);
    const MeshSegmentation& seg = mm.segmentation;  // built with the train (BuildGearTrain)
    for (const MeshSegment& s : seg.segments) {
      mt.boundary.push_back(s.tau_begin * mt.period);
      mt.k_drive.push_back(s.drive.stiffness);
      mt.k_back.push_back(s.back.stiffness);
      mt.error.push_back(s.unloaded_error);
      mt.drive_flank.push_back(s.drive);
      mt.back_flank.push_back(s.back);
      t.longest_segment = std::max(t.longest_segment, (s.tau_end - s.tau_begin) * mt.period);
    }
    mt.boundary.push_back(mt.period);
    // The errors repeat after whole revolutions of the gears that carry them.
    mt.errors = MeshErrorExcitation(mm.pair, seg);
    if (mt.errors.active()) {
      cycles_per_revolution.push_back(teeth * speed_a / t.input_speed /
                                      static_cast<double>(mt.errors.period_cycles()));
    }
    mt.half_backlash = 0.5 * spec.meshes[i].mesh.backlash;
    mt.displacement_limit = 2.0 * mt.half_backlash + WholeDepth(mm.geometry);
    mt.effective_mass = mm.effective_mass;
    mt.damping = mm.Damping();
    mt.transmitted_torque = mm.transmitted_torque;
    mt.friction = spec.meshes[i].mesh.friction_coefficient;
    FrictionBasis basis{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n),
                        Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
    basis.arm_a[mm.body_a] = 1.0;
    basis.arm_b[mm.body_b] = -1.0;
    SetFrictionForces(mt, basis);
    back_loaded.push_back(mm.back_flank_loaded);
    t.meshes.push_back(std::move(mt));
  }
  t.friction_loss_torque = FrictionLossTorque(t, back_loaded, topo.input_body);
  t.force[topo.input_body] += t.friction_loss_torque;
  AssignErrorInputs(t);
  const long revolutions =
      CommonPeriodRevolutions(cycles_per_revolution, options.max_common_period_revolutions);
  t.common_period = static_cast<double>(revolutions) * t.InputRevolution();
  t.gear_meshes = static_cast<int>(t.meshes.size());
  AddCouplingStages(train, t);
  return t;
}

TrainSystemCache::TrainSystemCache(const TrainTables& tables, const TrainTableOptions& options)
    : t_(tables), options_(options) {
  options.Validate();
  const int meshes = static_cast<int>(tables.meshes.size());
  key_words_ = std::max(1, (meshes + kMeshesPerWord - 1) / kMeshesPerWord);
  for (const TrainMeshTable& mt : tables.meshes) {
    if (3 * mt.segments() >= (1 << kBitsPerMesh)) {
      throw InputError("TrainTables.meshes.segments", 0, std::to_string(mt.segments()),
                       "must be < 21845 per mesh (tuple key width)");
    }
  }
  index_bits_ = kInitialIndexBits;
  index_.resize(size_t{1} << index_bits_);
  index_keys_.resize(index_.size() * static_cast<size_t>(key_words_));
  summary_.index_bytes = IndexBytes();
}

size_t TrainSystemCache::IndexBytes() const {
  return index_.size() * sizeof(Slot) + index_keys_.size() * sizeof(uint64_t);
}

size_t TrainSystemCache::Probe(const uint64_t* key) const {
  const size_t words = static_cast<size_t>(key_words_);
  // Fibonacci hashing: the top bits of the product mix every bit of the hash.
  size_t slot =
      (HashWords(key, words) * 0x9e3779b97f4a7c15ull) >> (64 - static_cast<unsigned>(index_bits_));
  const size_t mask = index_.size() - 1;
  while (index_[slot].used && !std::equal(key, key + words, &index_keys_[slot * words]))
    slot = (slot + 1) & mask;
  return slot;
}

void TrainSystemCache::GrowIndex() {
  const size_t words = static_cast<size_t>(key_words_);
  std::vector<Slot> old = std::move(index_);
  std::vector<uint64_t> old_keys = std::move(index_keys_);
  ++index_bits_;
  index_.assign(size_t{1} << index_bits_, Slot{});
  index_keys_.assign(index_.size() * words, 0);
  for (size_t i = 0; i < old.size(); ++i) {
    if (!old[i].used) continue;
    const uint64_t* key = &old_keys[i * words];
    const size_t slot = Probe(key);
    index_[slot] = old[i];
    std::copy(key, key + words, &index_keys_[slot * words]);
    if (old[i].held) entries_[old[i].entry].slot = slot;
  }
  summary_.index_bytes = IndexBytes();
}

namespace {

// Bytes a held tuple occupies: its matrices, closed forms, key and index entry.
size_t SystemBytes(const TrainSystem& s, size_t key_words) {
  size_t doubles = static_cast<size_t>(s.A.size() + s.balance.size());
  const SpectralDecomposition& d = s.decomposition;
  doubles += static_cast<size_t>(d.S.size() + d.S_inv.size() + d.B0.size() + d.block_sigma.size() +
                                 d.block_omega.size());
  size_t bytes = doubles * sizeof(double) + s.coupled_columns.size() * sizeof(int) +
                 d.blocks.size() * sizeof(SpectralDecomposition::Block) + sizeof(TrainSystem) +
                 2 * key_words * sizeof(uint64_t) + sizeof(uint64_t);
  for (const ClosedFormGap& gap : s.delta) bytes += gap.bytes();
  for (const ClosedFormGap& gap : s.delta_back) bytes += gap.bytes();
  return bytes;
}

}  // namespace

const TrainSystem& TrainSystemCache::Get(const std::vector<int>& segments,
                                         const std::vector<ContactState>& states, TupleKey& key) {
  std::fill(key.begin(), key.end(), 0);
  for (size_t i = 0; i < segments.size(); ++i) {
    const int segment = states[i] == ContactState::kFree ? 0 : segments[i];
    const uint64_t code = static_cast<uint64_t>(3 * segment + static_cast<int>(states[i]));
    key[i / kMeshesPerWord] |= code << (kBitsPerMesh * (i % kMeshesPerWord));
  }
  const size_t words = static_cast<size_t>(key_words_);
  // Consecutive pieces mostly stay on one tuple (the last one fetched): the same entry.
  if (recent_ != kNone) {
    Entry& e = entries_[recent_];
    if (std::equal(key.begin(), key.end(), &index_keys_[e.slot * words])) {
      ++summary_.hits;
      return e.system;
    }
  }
  size_t slot = Probe(key.data());
  if (index_[slot].held) {
    ++summary_.hits;
    recent_ = index_[slot].entry;
    Entry& e = entries_[recent_];
    e.used = ++tick_;
    return Enter(e);
  }
  ++summary_.misses;
  if (!index_[slot].used) {
    if (4 * (index_used_ + 1) > 3 * index_.size()) {
      GrowIndex();
      slot = Probe(key.data());
    }
    index_[slot].used = true;
    std::copy(key.begin(), key.end(), &index_keys_[slot * words]);
    ++index_used_;
  }
  if (free_entries_.empty()) {
    recent_ = entries_.size();
    entries_.emplace_back();
  } else {
    recent_ = free_entries_.back();
    free_entries_.pop_back();
  }
  Entry& e = entries_[recent_];
  e.system = Build(segments, states);
  e.system.bytes = SystemBytes(e.system, words);
  e.slot = slot;
  e.used = ++tick_;
  e.held = true;
  index_[slot].entry = recent_;
  index_[slot].held = true;
  summary_.bytes += e.system.bytes;
  ++summary_.tuples;
  return Enter(e);
}

const TrainSystem& TrainSystemCache::Enter(Entry& e) {
  const long visits = ++index_[e.slot].visits;
  if (!e.system.decomposed && visits >= options_.decompose_after_visits) {
    summary_.bytes -= e.system.bytes;
    Decompose(e.system);
    e.system.bytes = SystemBytes(e.system, static_cast<size_t>(key_words_));
    summary_.bytes += e.system.bytes;
    ++summary_.decompositions;
    if (!e.system.spectral) ++summary_.ill_conditioned;
  }
  Evict();
  return e.system;
}

void TrainSystemCache::Evict() {
  if (summary_.bytes > options_.cache_limit_bytes && summary_.tuples > 1) EvictOldest();
  summary_.peak_bytes = std::max(summary_.peak_bytes, summary_.bytes);
}

void TrainSystemCache::EvictOldest() {
  const size_t low_water = options_.cache_limit_bytes - options_.cache_limit_bytes / 8;
  eviction_order_.clear();
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (!entries_[i].held || i == recent_) continue;
    // Fewest visits first (the count survives eviction), then least recently used: a run whose
    // tuples recur in a cycle longer than the cache keeps a stable subset of them (hit rate ~
    // cache / cycle) where pure LRU would evict each one just before its next use.
    const uint64_t visits = static_cast<uint64_t>(index_[entries_[i].slot].visits);
    eviction_order_.emplace_back((std::min<uint64_t>(visits, 0xFFFFF) << 44) | entries_[i].used, i);
  }
  std::sort(eviction_order_.begin(), eviction_order_.end());
  for (const auto& [order, i] : eviction_order_) {
    if (summary_.bytes <= low_water) break;
    Entry& e = entries_[i];
    summary_.bytes -= e.system.bytes;
    index_[e.slot].held = false;
    index_[e.slot].entry = kNone;
    e.system = TrainSystem{};  // frees its tables
    e.held = false;
    free_entries_.push_back(i);
    --summary_.tuples;
    ++summary_.evictions;
  }
}

}  // namespace gearnvh
