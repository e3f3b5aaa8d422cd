// The preprint's strong-rattle operating point, like for like (issue 21, docs/BENCHMARKS.md §
// "The paper's operating point"):
//
//   bash scripts/bench.sh --paper [--quick] [--cpu-time] [--events K] [--train] [--cycles C]
//                                 [--json FILE] [--case S]
//
// examples/flexible_shafts.yaml at 7548.387097 rpm (mesh frequency 3.9 kHz, period 256 us),
// 20 N m, one engine order 15.5 of 200000 rad/s^2: 2.7-2.9 events per mesh cycle on every tier,
// the preprint's event rate. One core. Per-cycle cost = median of paired differences (runs of C
// and 2C cycles from the same start, back to back), so the set-up both runs pay cancels. Beside
// each pair: the matvec floor (Eigen matrix-vector products of the case's state dimension, 32
// matrices cycled as the solver cycles its segment propagators), so every cost is also quoted as
// a multiple of the work no event-driven method can avoid (the median of the pairs' ratios).
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "bench_common.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"

namespace {

using namespace gearnvh;
using namespace gearnvh::bench;

// --cpu-time: every duration is the thread's CPU time (CLOCK_THREAD_CPUTIME_ID) instead of wall
// time, so time slices given to other processes on a shared core are not counted (their cache
// pollution still is).
bool use_cpu_time = false;

double Seconds(const std::function<void()>& f) {
  if (!use_cpu_time) return SecondsOnce(f);
  timespec t0{}, t1{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
  f();
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
  return static_cast<double>(t1.tv_sec - t0.tv_sec) +
         1e-9 * static_cast<double>(t1.tv_nsec - t0.tv_nsec);
}

// One paired difference: `run(false)` then `run(true)`, back to back, on the clock above.
double PairedDifference(const std::function<void(bool longer)>& run) {
  const double short_run = Seconds([&] { run(false); });
  const double long_run = Seconds([&] { run(true); });
  return long_run - short_run;
}

// The preprint's figures (us per mesh cycle at its strong-rattle rate, one core).
constexpr double kPaperN40FullUs = 1282.0;
constexpr double kPaperN20MtaUs = 171.0;

GearboxSpec LoadedPoint() {
  GearboxSpec s = Example("flexible_shafts.yaml");
  s.operating.speed = 7548.387097 * std::numbers::pi / 30.0;
  return s;
}

// ns per matvec y = A_k x, A_k cycling over 32 random m x m matrices (the solver's working set
// at 64 segment propagators per cycle is of that size), stored as the V3 locator stores its dense
// matrices (rows padded with zeros to a multiple of 8) and multiplied by Eigen's product: up to 56
// rows the locator's own one-pass kernel is faster (~15 % at 48 x 46), at tier 1 its fixed-size one.
double MatvecFloorNs(int m, int repeats) {
  const int padded = (m + 7) / 8 * 8;
  std::vector<Eigen::MatrixXd> a(32, Eigen::MatrixXd::Zero(padded, m));
  for (auto& x : a) x.topRows(m).setRandom();
  Eigen::VectorXd x = Eigen::VectorXd::Random(m), y(padded);
  const long n = std::max<long>(20000, 40'000'000L / (static_cast<long>(m) * m));
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    t.push_back(Seconds([&] {
      for (long k = 0; k < n; ++k) {
        y.noalias() = a[k & 31] * x;
        x = y.head(m);
        x *= 0.5 / std::max(1.0, x.cwiseAbs().maxCoeff());  // keep the values finite
      }
    }));
  }
  // The rescale costs a pass over x; time it alone and subtract it.
  std::vector<double> rescale;
  for (int r = 0; r < repeats; ++r) {
    rescale.push_back(Seconds([&] {
      for (long k = 0; k < n; ++k) x *= 0.5 / std::max(1.0, x.cwiseAbs().maxCoeff());
    }));
  }
  return 1e9 * std::max(Median(t) - Median(rescale), 0.0) / static_cast<double>(n);
}

struct Settings {
  bool quick = false;
  int pairs = 5;
  long cycles = 1000, transient = 100;
};

struct Figures {
  SolverSummary summary;
  int m = 0;  // the state dimension
  double us_per_cycle = 0.0;
  // The matvec floor measured beside each pair (the median), and the median over the pairs of
  // each pair's cost over its own floor: this VM's speed drifts by up to ~1.5x over seconds, so a
  // floor measured minutes away from a case can be in another phase than the case.
  double floor_ns = 0.0;
  double ratio_to_floor = 0.0;
  double setup_ms = 0.0;  // the solver's per-run set-up (decompositions), model build excluded
  double build_ms = 0.0;  // spec -> component model -> reduced model -> tables
};

Figures Measure(const GearboxSpec& spec, Tier tier, LadderMethod method, bool record,
                double carry_max_error, bool cycle_rows, const Settings& s, long cycles) {
  Figures f;
  OperatingPointModel op;
  f.build_ms = 1e3 * Seconds([&] { op = BuildOperatingPointModel(spec, tier); });
  f.m = op.tables.m;
  const auto [z0, s0] = StaticInitialState(op.tables);
  SolverOptions o;
  ApplyLadderMethod(method, o);
  o.carry_max_error = carry_max_error;
  o.cycle_rows = cycle_rows;
  o.transient_cycles = s.transient;
  o.record_trajectory = record;
  std::vector<double> differences, floors;
  for (int p = 0; p < s.pairs; ++p) {
    differences.push_back(PairedDifference([&](bool longer) {
      o.cycles = longer ? 2 * cycles : cycles;
      const SolverResult r = SimulateExact(op.tables, z0, s0, o);
      if (longer) f.summary = r.summary;
    }));
    // After the pair, so its own matrices do not evict the tables before the short run.
    floors.push_back(MatvecFloorNs(f.m, 1));
  }
  f.us_per_cycle = 1e6 * std::max(Median(differences), 0.0) / static_cast<double>(cycles);
  f.floor_ns = Median(floors);
  std::vector<double> ratios;
  for (size_t p = 0; p < differences.size(); ++p) {
    ratios.push_back(1e9 * std::max(differences[p], 0.0) / static_cast<double>(cycles) /
                     (f.summary.matvec_per_cycle * floors[p]));
  }
  f.ratio_to_floor = Median(ratios);
  // Set-up: the median of 3 one-cycle runs (each builds its own decompositions).
  o.cycles = 1;
  o.transient_cycles = 0;
  std::vector<double> setups;
  for (int k = 0; k < 3; ++k)
    setups.push_back(1e3 * Seconds([&] { SimulateExact(op.tables, z0, s0, o); }));
  f.setup_ms = Median(setups);
  return f;
}

// The events of `cycles` mesh cycles after `transient` ones, V3 with and without the carry in
// decoupled coordinates, from the same start: counts and the largest time difference (in units of
// the first segment's length). Rattle amplifies rounding differences from impact to impact, so
// the horizon is short.
void CompareCarriedEvents(const GearboxSpec& spec, Tier tier, long transient, long cycles) {
  const OperatingPointModel op = BuildOperatingPointModel(spec, tier);
  const auto [z0, s0] = StaticInitialState(op.tables);
  SolverOptions o;
  ApplyLadderMethod(LadderMethod::kV3, o);
  o.record_trajectory = false;
  ExactStepper settle(op.tables, o, z0, s0, 0, 0);
  settle.Run(transient, false);
  std::vector<EventRecord> events[2];
  for (int carried = 0; carried < 2; ++carried) {
    o.carry_max_error = carried == 1 ? SolverOptions{}.carry_max_error : 0.0;
    ExactStepper stepper(op.tables, o, settle.state(), settle.contact(), 0, 4096);
    stepper.Run(cycles, true);
    events[carried] = stepper.trajectory().events;
  }
  const double h = op.tables.SegmentLength(0);
  double worst = 0.0;
  size_t same_kind = 0;
  for (size_t i = 0; i < std::min(events[0].size(), events[1].size()); ++i) {
    if (events[0][i].to != events[1][i].to) break;
    ++same_kind;
    worst = std::max(worst, std::abs(events[0][i].time - events[1][i].time));
  }
  fmt::print(
      "    events over {} cycles: {} uncarried, {} carried, {} alike in order, largest time "
      "difference {:.2g} h\n",
      cycles, events[0].size(), events[1].size(), same_kind, worst / h);
}

// --train: the same gearbox read as its one-mesh train (TrainOf -> BuildGearTrain -> tables at the
// tier -> TrainStepper, V3, unrecorded, no certified jumps), per cycle as Measure's pairs: the gap
// issue 37's one pipeline must close (at most 10 % over the pair's figure). Its events per cycle
// beside it, so the comparison is like for like.
struct TrainPath {
  double us_per_cycle = 0.0, events_per_cycle = 0.0;
  bool completed = true;
};

TrainPath MeasureTrainPath(const GearboxSpec& spec, Tier tier, const Settings& s, long cycles) {
  const TrainSpec train_spec = TrainOf(spec);
  const TrainTables t = BuildTrainTablesAtTier(train_spec, BuildGearTrain(train_spec), tier, {});
  const auto [z0, s0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = false;
  const double period = t.meshes.front().period;
  TrainPath out;
  std::vector<double> differences;
  for (int p = 0; p < s.pairs; ++p) {
    differences.push_back(PairedDifference([&](bool longer) {
      TrainStepper stepper(t, options, z0, s0);
      const long run = longer ? 2 * cycles : cycles;
      out.completed = stepper.Run(static_cast<double>(run) * period) && out.completed;
      if (longer) out.events_per_cycle = static_cast<double>(stepper.summary().events) / run;
    }));
  }
  out.us_per_cycle = 1e6 * std::max(Median(differences), 0.0) / static_cast<double>(cycles);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  std::string json_file, only;
  long event_cycles = 0;  // --events K: the carried/uncarried event comparison of each V3 case
  bool train_path = false;  // --train: each unrecorded V3 case also through the one-mesh train
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      s.quick = true;
      s.pairs = 3;
      s.cycles = 300;
      s.transient = 50;
    } else if (std::strcmp(argv[i], "--events") == 0 && i + 1 < argc) {
      event_cycles = std::max(1L, std::atol(argv[++i]));
    } else if (std::strcmp(argv[i], "--train") == 0) {
      train_path = true;
    } else if (std::strcmp(argv[i], "--cpu-time") == 0) {
      use_cpu_time = true;
    } else if (std::strcmp(argv[i], "--json") == 0 && i + 1 < argc) {
      json_file = argv[++i];
    } else if (std::strcmp(argv[i], "--cycles") == 0 && i + 1 < argc) {
      s.cycles = std::max(1L, std::atol(argv[++i]));
    } else if (std::strcmp(argv[i], "--case") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      fmt::print(
          stderr,
          "usage: {} [--quick] [--cpu-time] [--events K] [--train] [--cycles C] [--json FILE] "
          "[--case S]\n",
          argv[0]);
      return 2;
    }
  }
  const double mesh_period_us = 1e6 / 3900.0;
  fmt::print(
      "gearnvh at the preprint's strong-rattle point — {} — one core — {} + {} transient cycles, "
      "median of {} paired differences, {} time\n",
      Machine(), s.cycles, s.transient, s.pairs, use_cpu_time ? "thread CPU" : "wall");

  std::map<int, std::vector<double>> floor_ns;  // state dimension -> each case's floor, ns

  fmt::print("\n  {:<40} {:>6} {:>4} {:>7} {:>8} {:>9} {:>8} {:>9} {:>9} {:>9} {:>9}\n", "case",
             "C", "m", "ev/cyc", "matvec/c", "us/cycle", "x real", "x paper", "floor us", "x floor",
             "setup ms");
  struct Case {
    const char* label;
    GearboxSpec spec;
    Tier tier;
    LadderMethod method;
    bool record;
    double paper_us;  // 0: the preprint has no figure for it
    // V3's carry in decoupled coordinates (SolverOptions::carry_max_error; 0: off, as before).
    double carry_max_error = SolverOptions{}.carry_max_error;
    bool cycle_rows = true;  // SolverOptions::cycle_rows
    // At least this many cycles per run: a per-cycle cost of a few us must stand out of the
    // set-up's jitter (the runs share a ~0.5 s set-up on N40 full).
    long min_cycles = 0;
  };
  const GearboxSpec paper = PaperPoint();
  const Case cases[] = {
      {"tier 1, v3 uncarried", paper, Tier::kTier1, LadderMethod::kV3, false, 0.0, 0.0},
      {"tier 1, v3", paper, Tier::kTier1, LadderMethod::kV3, false, 0.0},
      {"tier 1, fused", paper, Tier::kTier1, LadderMethod::kFused, false, 0.0},
      {"N20 MTA, v3 uncarried", paper, Tier::kN20Mta, LadderMethod::kV3, false, kPaperN20MtaUs,
       0.0},
      {"N20 MTA, v3", paper, Tier::kN20Mta, LadderMethod::kV3, false, kPaperN20MtaUs},
      {"N20 MTA, fused", paper, Tier::kN20Mta, LadderMethod::kFused, false, kPaperN20MtaUs},
      {"N40 full, v3 uncarried", paper, Tier::kTier5, LadderMethod::kV3, false, kPaperN40FullUs,
       0.0},
      {"N40 full, v3", paper, Tier::kTier5, LadderMethod::kV3, false, kPaperN40FullUs},
      {"N40 full, fused", paper, Tier::kTier5, LadderMethod::kFused, false, kPaperN40FullUs},
      {"N40 full, fused, recorded", paper, Tier::kTier5, LadderMethod::kFused, true,
       kPaperN40FullUs},
      {"loaded N40 full, recorded", LoadedPoint(), Tier::kTier5, LadderMethod::kFused, true, 0.0,
       SolverOptions{}.carry_max_error, true, 50000},
      // The same run recorded one matvec per segment and piece by piece (before output rows).
      {"loaded N40 full, recorded, per segment", LoadedPoint(), Tier::kTier5, LadderMethod::kFused,
       true, 0.0, SolverOptions{}.carry_max_error, false},
  };
  nlohmann::json rows = nlohmann::json::array();
  for (const Case& c : cases) {
    // --case S: the cases whose label contains S, or the one case whose label is S.
    const bool exact = std::any_of(std::begin(cases), std::end(cases),
                                   [&](const Case& k) { return only == k.label; });
    if (exact ? only != c.label : std::string(c.label).find(only) == std::string::npos) continue;
    const long cycles = std::max(s.cycles, s.quick ? c.min_cycles / 5 : c.min_cycles);
    const Figures f =
        Measure(c.spec, c.tier, c.method, c.record, c.carry_max_error, c.cycle_rows, s, cycles);
    const int m = f.m;
    floor_ns[m].push_back(f.floor_ns);
    const double floor_us = 1e-3 * f.floor_ns * f.summary.matvec_per_cycle;
    const double paper_ratio = c.paper_us > 0.0 ? c.paper_us / f.us_per_cycle : 0.0;
    fmt::print(
        "  {:<40} {:>6} {:>4} {:>7.2f} {:>8.1f} {:>9.2f} {:>8.2f} {:>9} {:>9.2f} {:>9.2f} "
        "{:>9.1f}\n",
        c.label, cycles, m, f.summary.events_per_cycle, f.summary.matvec_per_cycle, f.us_per_cycle,
        mesh_period_us / f.us_per_cycle,
        paper_ratio > 0.0 ? fmt::format("{:.1f}", paper_ratio) : "-", floor_us, f.ratio_to_floor,
        f.setup_ms);
    rows.push_back({{"case", c.label},
                    {"state_dim", m},
                    {"cycles", cycles},
                    {"cycle_rows", c.cycle_rows},
                    {"recorded", c.record},
                    {"events_per_cycle", f.summary.events_per_cycle},
                    {"matvec_per_cycle", f.summary.matvec_per_cycle},
                    {"us_per_cycle", f.us_per_cycle},
                    {"real_time_ratio", mesh_period_us / f.us_per_cycle},
                    {"paper_us_per_cycle", c.paper_us},
                    {"speedup_vs_paper", paper_ratio},
                    {"matvec_floor_us_per_cycle", floor_us},
                    {"ratio_to_floor", f.ratio_to_floor},
                    {"solver_setup_ms", f.setup_ms},
                    {"model_build_ms", f.build_ms},
                    {"table_bytes", f.summary.table_bytes},
                    {"carried_systems", f.summary.carried_systems},
                    {"carry_error_bound", f.summary.carry_error_bound},
                    {"spectral_max_condition", f.summary.spectral_max_condition}});
    if (event_cycles > 0 && c.method == LadderMethod::kV3 && c.carry_max_error > 0.0)
      CompareCarriedEvents(c.spec, c.tier, s.transient, event_cycles);
    fmt::print("    carried pairs {}, carry error bound {:.2g}, max cond(S) {:.3g}\n",
               f.summary.carried_systems, f.summary.carry_error_bound,
               f.summary.spectral_max_condition);
    if (train_path && c.method == LadderMethod::kV3 && !c.record) {
      const TrainPath tp = MeasureTrainPath(c.spec, c.tier, s, cycles);
      fmt::print(
          "    one-mesh train path: {:.2f} us/cycle, {:.2f} x this case, {:.2f} events/cycle{}\n",
          tp.us_per_cycle, f.us_per_cycle > 0.0 ? tp.us_per_cycle / f.us_per_cycle : 0.0,
          tp.events_per_cycle, tp.completed ? "" : " (a run stopped: not comparable)");
      rows.back()["train_path_us_per_cycle"] = tp.us_per_cycle;
      rows.back()["train_path_events_per_cycle"] = tp.events_per_cycle;
    }
  }
  fmt::print("\n  matvec floor (ns per product, 32 matrices cycled; each case's, in order):");
  nlohmann::json floors = nlohmann::json::object();
  for (const auto& [m, ns] : floor_ns) {
    fmt::print("  m = {}: {:.0f}", m, fmt::join(ns, " / "));
    floors[std::to_string(m)] = ns;
  }
  fmt::print("\n");
  if (!json_file.empty()) {
    const nlohmann::json doc = {{"machine", Machine()}, {"mesh_period_us", mesh_period_us},
                                {"cycles", s.cycles},   {"pairs", s.pairs},
                                {"runs", rows},         {"matvec_floor_ns", floors}};
    std::ofstream(json_file) << doc.dump(1) << "\n";
    fmt::print("JSON: {}\n", json_file);
  }
  return 0;
}
