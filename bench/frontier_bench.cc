// The real-time frontier, measured (issue 9, docs/design.md §9): one table and one JSON document.
//
//   bash scripts/bench.sh [--quick] [--json FILE]
//
// Operating points (mesh frequency 3.9 kHz, a 256 us mesh period, as in the preprint):
//   strong rattle   examples/idle_rattle.yaml at 8667 rpm, 10 N m: near the 4.1 kHz mesh mode the
//                   pair loses contact and re-impacts every mesh cycle (2.0 events per cycle)
//   sparse contact  the same at its own 0.2 N m drag: double-sided rattle, ~0.28 events per cycle
//   loaded          examples/flexible_shafts.yaml at 7548 rpm, 200 N m: permanent contact
//   flexible rattle examples/flexible_shafts.yaml at 7548 rpm, 2 N m with the idle example's
//                   2nd-order excitation (1500 rad/s^2): tiers 1-5 with impacts
// Timing: one core unless stated. Stepping cost per cycle is the marginal cost, the median of
// `repeats` paired differences (a run of 2C cycles minus one of C, back to back); the set-up each
// run pays (V3 decompositions, V1 tables) is its own column; other figures are the best of
// `repeats`. Wall-clock numbers depend on the machine, ratios within one run do not.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <thread>

#include "bench_common.h"
#include "config/gearbox_loader.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/reference_integrator.h"

namespace {

using namespace gearnvh;
using bench::Clock;

struct Settings {
  bool quick = false;
  int repeats = 3;
  long cycles = 2000, transient = 200;
};

double Seconds(const std::function<void()>& f, int repeats) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) best = std::min(best, bench::SecondsOnce(f));
  return best;
}

using bench::Example;
using bench::Machine;

GearboxSpec At3900Hz(GearboxSpec spec) {
  spec.operating.speed = 2.0 * std::numbers::pi * 3900.0 / spec.pinion.teeth;
  return spec;
}

GearboxSpec StrongRattle() {
  GearboxSpec s = At3900Hz(Example("idle_rattle.yaml"));
  s.operating.torque = 10.0;
  return s;
}
GearboxSpec SparseContact() { return At3900Hz(Example("idle_rattle.yaml")); }
GearboxSpec Loaded() { return At3900Hz(Example("flexible_shafts.yaml")); }
GearboxSpec FlexibleRattle() {
  GearboxSpec s = Loaded();
  s.operating.torque = 2.0;
  s.operating.excitation = {{2.0, 1500.0, 0.0}};
  return s;
}

struct Built {
  ComponentModel model;
  ReducedModel reduced;
  SegmentTables tables;
  Built(const GearboxSpec& spec, Tier tier)
      : model(BuildComponentModel(spec)),
        reduced(ReduceModel(model, tier)),
        tables(BuildSegmentTables(model, reduced, spec)) {}
};

struct RunFigures {
  SolverSummary summary;
  double wall_s = 0.0;   // stepping only: the cycles' cost without the table set-up
  double setup_s = 0.0;  // the solver's per-run set-up (V3 decompositions, V1 dyadic tables)
  double te_rms = 0.0;
};

// The per-cycle cost is the median paired difference of runs of C and 2C cycles (same start), so
// the set-up each SimulateExact call pays (decompositions, dyadic tables) is reported apart.
RunFigures TimeRun(const Built& b, LadderMethod method, const Settings& s) {
  const auto [z0, s0] = StaticInitialState(b.tables);
  SolverOptions o;
  ApplyLadderMethod(method, o);
  o.transient_cycles = s.transient;
  o.record_trajectory = true;
  RunFigures f;
  double long_run_s = 0.0;
  const double marginal = bench::PairedMarginalSeconds(
      [&](bool longer) {
        o.cycles = longer ? 2 * s.cycles : s.cycles;
        const auto t0 = Clock::now();
        const SolverResult r = SimulateExact(b.tables, z0, s0, o);
        if (longer) {
          long_run_s = std::chrono::duration<double>(Clock::now() - t0).count();
          f.summary = r.summary;
          f.te_rms = ComputeTransmissionErrorStats(r.trajectory, 0.0, 0.0).rms;
        }
      },
      s.repeats);
  // Stepping cost of all 2C + transient cycles, extrapolated from the marginal cost of C cycles.
  const double per_cycle = std::max(marginal, 1e-12) / static_cast<double>(s.cycles);
  f.wall_s = per_cycle * static_cast<double>(f.summary.mesh_cycles);
  f.setup_s = std::max(0.0, long_run_s - f.wall_s);
  return f;
}

nlohmann::json Row(const std::string& section, const std::string& name, const Built& b,
                   const RunFigures& f) {
  const double cycles = static_cast<double>(f.summary.mesh_cycles);
  const double simulated = cycles * b.tables.mesh_period;
  return {{"section", section},
          {"case", name},
          {"state_dim", b.tables.m},
          {"events_per_cycle", f.summary.events_per_cycle},
          {"matvec_per_cycle", f.summary.matvec_per_cycle},
          {"ns_per_segment_step", 1e9 * f.wall_s / (cycles * b.tables.segments())},
          {"us_per_cycle", 1e6 * f.wall_s / cycles},
          {"real_time_ratio", simulated / f.wall_s},
          {"table_bytes", f.summary.table_bytes},
          {"setup_ms", 1e3 * f.setup_s},
          {"te_rms_m", f.te_rms}};
}

void PrintRow(const nlohmann::json& r) {
  fmt::print("  {:<34} {:>5} {:>8.2f} {:>9.1f} {:>9.1f} {:>9.2f} {:>9.2f} {:>10.0f} {:>9.1f}\n",
             r["case"].get<std::string>(), r["state_dim"].get<int>(),
             r["events_per_cycle"].get<double>(), r["matvec_per_cycle"].get<double>(),
             r["ns_per_segment_step"].get<double>(), r["us_per_cycle"].get<double>(),
             r["real_time_ratio"].get<double>(), r["table_bytes"].get<double>() / 1024.0,
             r["setup_ms"].get<double>());
}

void Header(const std::string& title) {
  fmt::print("\n{}\n  {:<34} {:>5} {:>8} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9}\n", title, "case",
             "m", "ev/cyc", "matvec/c", "ns/step", "us/cycle", "x real", "table KiB", "setup ms");
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  std::string json_file;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      s.quick = true;
      s.repeats = 1;
      s.cycles = 400;
      s.transient = 100;
    } else if (std::strcmp(argv[i], "--json") == 0 && i + 1 < argc) {
      json_file = argv[++i];
    } else {
      fmt::print(stderr, "usage: {} [--quick] [--json FILE]\n", argv[0]);
      return 2;
    }
  }
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  fmt::print(
      "gearnvh frontier benchmark — {} — {} cores — {} recorded + {} transient cycles, median "
      "of {} paired differences\n",
      Machine(), cores, s.cycles, s.transient, s.repeats);
  nlohmann::json rows = nlohmann::json::array();
  auto add = [&](const std::string& section, const std::string& name, const Built& b,
                 const RunFigures& f) {
    rows.push_back(Row(section, name, b, f));
    PrintRow(rows.back());
  };

  // 1. Step cost per tier, rattle and loaded (V3 stepping: every segment stepped).
  Header("1. Step cost per tier at 3.9 kHz (v3, stepped)");
  const std::pair<const char*, Tier> tiers[] = {{"tier 1", Tier::kTier1},
                                                {"tier 2", Tier::kTier2},
                                                {"tier 3", Tier::kTier3},
                                                {"tier 4", Tier::kTier4},
                                                {"tier 5 (N40 full)", Tier::kTier5}};
  for (const auto& [label, tier] : tiers) {
    const Built b(FlexibleRattle(), tier);
    add("step_cost", std::string("flexible rattle, ") + label, b, TimeRun(b, LadderMethod::kV3, s));
  }
  for (const auto& [label, tier] : tiers) {
    const Built b(Loaded(), tier);
    add("step_cost", std::string("loaded, ") + label, b, TimeRun(b, LadderMethod::kV3, s));
  }

  // 2. Constant contact: one fused cycle and a certified jump of 10^6 cycles.
  fmt::print("\n2. Constant contact (loaded example at 3.9 kHz)\n");
  nlohmann::json contact = nlohmann::json::array();
  for (const auto& [label, tier] :
       {std::pair<const char*, Tier>{"tier 1", Tier::kTier1}, {"N20 MTA", Tier::kN20Mta}}) {
    const Built b(Loaded(), tier);
    const ConstantContactCycle cycle(b.tables, ContactState::kDrive);
    auto [z, st] = StaticInitialState(b.tables);
    Eigen::VectorXd w(z.size());
    const long n = s.quick ? 20000 : 200000;
    const double per_cycle = Seconds(
                                 [&] {
                                   for (long k = 0; k < n; ++k) {
                                     w.noalias() = cycle.map() * z;
                                     z.swap(w);
                                   }
                                 },
                                 s.repeats) /
                             static_cast<double>(n);
    Eigen::VectorXd jumped;
    const double jump = Seconds([&] { jumped = cycle.Jump(z, 1000000); }, std::max(3, s.repeats));
    const bool certified = cycle.Certify(z).certified;
    contact.push_back({{"case", label},
                       {"state_dim", b.tables.m},
                       {"ns_per_fused_cycle", 1e9 * per_cycle},
                       {"ns_per_jump_1e6_cycles", 1e9 * jump},
                       {"certified", certified}});
    fmt::print(
        "  {:<12} m = {:>3}: fused cycle {:8.1f} ns, certified jump of 10^6 cycles {:9.1f} "
        "ns{}\n",
        label, b.tables.m, 1e9 * per_cycle, 1e9 * jump, certified ? "" : " (certificate refused)");
  }

  // 3. Event paths: strong rattle and sparse contact, V1 / V2 / V3 / fused (tier 1).
  Header("3. Event location, tier 1 at 3.9 kHz");
  for (const auto& [label, spec] :
       {std::pair<const char*, GearboxSpec>{"strong rattle", StrongRattle()},
        {"sparse contact", SparseContact()}}) {
    const Built b(spec, Tier::kTier1);
    for (const LadderMethod method : kLadderMethods) {
      add("events", std::string(label) + ", " + LadderMethodName(method), b, TimeRun(b, method, s));
    }
  }

  // 4. Flexible tier (loaded).
  Header("4. Flexible tiers, loaded example at 3.9 kHz");
  for (const auto& [label, tier, method] :
       {std::tuple<const char*, Tier, LadderMethod>{"N40 full", Tier::kTier5, LadderMethod::kV3},
        {"N20 simple", Tier::kN20Simple, LadderMethod::kV3},
        {"N20 MTA", Tier::kN20Mta, LadderMethod::kV3},
        {"N20 MTA + fusion", Tier::kN20Mta, LadderMethod::kFused},
        {"N40 full + fusion", Tier::kTier5, LadderMethod::kFused}}) {
    const Built b(Loaded(), tier);
    add("flexible", label, b, TimeRun(b, method, s));
  }

  // 5. The peer: CVODE (BDF, dense, exact Jacobian, rootfinding) on the same piecewise model,
  // tuned to the exact solver's TE RMS (1e-6 relative) over a short strong-rattle record.
  fmt::print("\n5. Brute-force peer (CVODE) at matched TE accuracy, strong rattle, {} cycles\n",
             s.quick ? 20 : 60);
  nlohmann::json peer = nlohmann::json::array();
  for (const auto& [label, tier] : {std::pair<const char*, Tier>{"tier 1", Tier::kTier1},
                                    {"tier 2", Tier::kTier2},
                                    {"tier 3", Tier::kTier3}}) {
    const Built b(StrongRattle(), tier);
    const auto [z0, s0] = StaticInitialState(b.tables);
    const long cycles = s.quick ? 20 : 60;
    SolverOptions o;
    ApplyLadderMethod(LadderMethod::kV3, o);
    o.cycles = cycles;
    SolverResult exact;
    const double exact_s = Seconds([&] { exact = SimulateExact(b.tables, z0, s0, o); }, s.repeats);
    const double exact_rms = ComputeTransmissionErrorStats(exact.trajectory, 0.0, 0.0).rms;
    double matched_rtol = 0.0, peer_s = 0.0, peer_error = 0.0;
    long steps = 0;
    for (double rtol : {1e-6, 1e-8, 1e-10, 1e-12}) {
      ReferenceOptions ro;
      ro.cycles = cycles;
      ro.rtol = rtol;
      ReferenceResult ref;
      const double t = Seconds([&] { ref = SimulateReference(b.tables, z0, s0, ro); }, 1);
      if (ref.status != ReferenceStatus::kSuccess) continue;
      const double rms = ComputeTransmissionErrorStats(ref.trajectory, 0.0, 0.0).rms;
      peer_error = std::abs(rms - exact_rms) / exact_rms;
      peer_s = t;
      steps = ref.steps;
      matched_rtol = rtol;
      if (peer_error <= 1e-6) break;
    }
    peer.push_back({{"case", label},
                    {"state_dim", b.tables.m},
                    {"exact_s", exact_s},
                    {"peer_s", peer_s},
                    {"peer_rtol", matched_rtol},
                    {"peer_steps", steps},
                    {"peer_te_rms_error", peer_error},
                    {"speedup", peer_s / exact_s}});
    fmt::print(
        "  {:<8} m = {:>3}: exact {:8.2f} ms, CVODE {:9.1f} ms (rtol {:.0e}, {} steps, TE "
        "RMS error {:.1e}) -> exact is {:.0f}x faster\n",
        label, b.tables.m, 1e3 * exact_s, 1e3 * peer_s, matched_rtol, steps, peer_error,
        peer_s / exact_s);
  }

  // 6. Atlas throughput: cells/s on 1 and all cores.
  fmt::print("\n6. Chaos atlas throughput (idle example, 540 + 270 cycles per cell)\n");
  const GearboxSpec idle = Example("idle_rattle.yaml");
  AtlasAxis x{"operating.speed",
              {600.0 * std::numbers::pi / 30.0, 3000.0 * std::numbers::pi / 30.0, s.quick ? 2 : 4}};
  AtlasAxis y{"operating.torque", {0.05, 0.5, s.quick ? 2 : 4}};
  AtlasOptions ao;
  ao.cycles = 540;
  ao.transient_cycles = 270;
  ao.threads = 1;
  const double one = Seconds([&] { RunChaosAtlas(idle, x, y, ao); }, 1);
  ao.threads = static_cast<int>(cores);
  const double all = Seconds([&] { RunChaosAtlas(idle, x, y, ao); }, 1);
  const double cells = static_cast<double>(x.range.points * y.range.points);
  const nlohmann::json atlas = {{"cells", cells},
                                {"cells_per_s_1_core", cells / one},
                                {"cells_per_s_all_cores", cells / all},
                                {"cores", cores},
                                {"parallel_efficiency", one / all / cores}};
  fmt::print(
      "  {} cells: {:.2f} cells/s on 1 core, {:.2f} cells/s on {} cores, parallel "
      "efficiency {:.0f} %\n",
      cells, cells / one, cells / all, cores, 100.0 * one / all / cores);

  // 7. Reduction of a finely meshed shaft model.
  fmt::print("\n7. Reduction: flexible example with 1 mm shaft elements\n");
  GearboxSpec fine = Example("flexible_shafts.yaml");
  fine.input_shaft->element_length = 1e-3;
  fine.output_shaft->element_length = 1e-3;
  ComponentModel model;
  const double build = Seconds([&] { model = BuildComponentModel(fine); }, 1);
  ReducedModel r5, r20;
  const double tier5 = Seconds([&] { r5 = ReduceModel(model, Tier::kTier5); }, s.repeats);
  const double mta = Seconds([&] { r20 = ReduceModel(model, Tier::kN20Mta); }, s.repeats);
  const nlohmann::json reduction = {{"elements", model.nodes.size() - 2},
                                    {"dof", model.dofs},
                                    {"build_s", build},
                                    {"reduce_n40_full_s", tier5},
                                    {"reduce_n20_mta_s", mta}};
  fmt::print("  {} DOF: build {:.0f} ms, reduce to N40 full {:.0f} ms, to N20 MTA {:.0f} ms\n",
             model.dofs, 1e3 * build, 1e3 * tier5, 1e3 * mta);

  const nlohmann::json doc = {{"machine", Machine()},
                              {"cores", cores},
                              {"quick", s.quick},
                              {"cycles", s.cycles},
                              {"transient_cycles", s.transient},
                              {"runs", rows},
                              {"constant_contact", contact},
                              {"peer", peer},
                              {"atlas", atlas},
                              {"reduction", reduction}};
  if (!json_file.empty()) {
    std::ofstream(json_file) << doc.dump(1) << "\n";
    fmt::print("\nJSON: {}\n", json_file);
  }
  return 0;
}
