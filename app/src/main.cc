// gearnvh: the command line. Exit codes (command_errors.h, docs/cli.md): 0 ok, 1 invalid input,
// 2 usage error, 3 internal error, 4 I/O error.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <type_traits>

#include "atlas_command.h"
#include "check_command.h"
#include "cleanup_on_exit.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh_revision.h"
#include "mpi_context.h"
#include "orbits_command.h"
#include "tiers_command.h"
#ifdef GEARNVH_HAVE_RENDER
#include "report_command.h"
#endif
#include "config/train_parameters.h"
#include "simulate_command.h"
#include "sweep_command.h"
#include "validate_command.h"
#include "whine_command.h"

namespace {

// CLI11 prefixes a validator's message with the option's name: the message without the error's
// own path ("--tier: ...") so that the name is not printed twice.
std::string RuleAndValue(const gearnvh::InputError& e) {
  return e.rule() + (e.value().empty() ? "" : ", got " + e.value());
}

// CLI11's help shows an option's type name followed by each validator's description after a
// colon ("INT:INT in [1, 64]"). The validators here have no description; the option's type name
// alone says what it takes ("INT in [1, 64]", "TIER").
CLI::Option* Checked(CLI::Option* option, CLI::Validator check, const std::string& shown) {
  return option->check(std::move(check))->type_name(shown);
}

// Option values checked while the command line is parsed, so a bad one is a usage error (2):
// `parse` throws InputError on a bad value.
template <typename Parse>
CLI::Validator ParsedBy(Parse parse) {
  return CLI::Validator(
      [parse](std::string& text) -> std::string {
        try {
          (void)parse(text);
          return {};
        } catch (const gearnvh::InputError& e) {
          return RuleAndValue(e);
        }
      },
      "");
}

// An option in [min, max] (an integer for integral T), its message in the user's terms ("must be
// an integer from 1 to 1000000, got 1.5"): CLI11's Range says "Value 1.5 not in range 1 to
// 1000000" and prints the bounds of a double as "36.000000". Help: "INT in [1, 1000000]".
template <typename T>
CLI::Option* CheckRange(CLI::Option* option, T min, T max) {
  constexpr bool kInteger = std::is_integral_v<T>;
  const std::string rule =
      fmt::format("must be {} from {} to {}", kInteger ? "an integer" : "a number", min, max);
  return Checked(option,
                 CLI::Validator(
                     [min, max, rule](std::string& text) -> std::string {
                       T value{};
                       const char* end = text.data() + text.size();
                       const auto [stop, error] = std::from_chars(text.data(), end, value);
                       const bool whole = error == std::errc() && stop == end;
                       return whole && value >= min && value <= max ? std::string()
                                                                    : rule + ", got " + text;
                     },
                     ""),
                 fmt::format("{} in [{}, {}]", kInteger ? "INT" : "NUMBER", min, max));
}

// --tier, checked by ParseTier while the command line is parsed.
void AddTierOption(CLI::App* command, std::optional<std::string>& tier,
                   const std::string& help = "Modal tier (default: analysis.tier)") {
  Checked(command->add_option("--tier", tier, help),
          ParsedBy([](const std::string& text) { return gearnvh::app::ParseTier(text); }), "TIER");
}

void AddJobsOption(CLI::App* command, int& jobs,
                   const std::string& help = "Threads (default: all cores)") {
  CheckRange(command->add_option("--jobs", jobs, help), 1, 1024);
}

// --width, --height and --dpi of the images a command draws; `image` names them in the help
// ("tiers.png").
void AddImageSizeOptions(CLI::App* command, int& width, int& height, double& dpi,
                         const std::string& image) {
  CheckRange(command->add_option("--width", width, image + " width in pixels (default 1200)"), 200,
             8000);
  CheckRange(command->add_option("--height", height, image + " height in pixels (default 800)"),
             150, 8000);
  CheckRange(command->add_option("--dpi", dpi, image + " DPI, scales the fonts (default 100)"),
             36.0, 600.0);
}

// --method, read into `method` by ParseMethod while the command line is parsed.
CLI::Option* AddMethodOption(CLI::App* command, gearnvh::LadderMethod& method,
                             const std::string& help) {
  return Checked(
      command->add_option_function<std::string>(
          "--method",
          [&method](const std::string& text) { method = gearnvh::app::ParseMethod(text); }, help),
      ParsedBy([](const std::string& text) { return gearnvh::app::ParseMethod(text); }), "METHOD");
}

// An axis of either schema's parameters (the file, read later, decides which apply; the command
// then refuses a parameter of the other schema with its own message). An atlas axis (`grid`) also
// keeps the rules of the file's analysis.atlas axes.
CLI::Option* CheckAxis(CLI::Option* option, const std::string& flag, bool grid = false) {
  const CLI::Validator axis(
      [flag, grid](std::string& text) -> std::string {
        gearnvh::AtlasAxis parsed;
        try {
          parsed = gearnvh::config::ParseAxisOption(text, flag);
        } catch (const gearnvh::InputError& pair_error) {
          const std::string name = text.substr(0, text.find('='));
          const bool train_form = gearnvh::app::TrainParameterDimension(name).has_value() ||
                                  name.rfind("meshes", 0) == 0 ||
                                  name.rfind("operating.loads", 0) == 0;
          if (!train_form) return RuleAndValue(pair_error);
          try {
            parsed = gearnvh::app::ParseTrainAxisOption(text, flag);
          } catch (const gearnvh::InputError& train_error) {
            return RuleAndValue(train_error);
          }
        }
        if (!grid) return {};
        try {
          gearnvh::app::RequireAtlasAxisRange(parsed, text, flag);
        } catch (const gearnvh::InputError& e) {
          return e.rule() + ", got '" + text + "'";
        }
        return {};
      },
      "");
  return Checked(option, axis, "PARAMETER=FROM:TO:N");
}

int Main(int argc, char** argv) {
  CLI::App app{
      "gearnvh: gearbox NVH from a YAML gearbox definition (schema gearnvh/1, one pair, or\n"
      "gearnvh/2, a gear train).\n"
      "Mesh stiffness, flexible shafts, modal tiers, exact gear-rattle dynamics, NVH reports."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("gearnvh ") + GEARNVH_VERSION + " (git " +
                                        GEARNVH_GIT_REVISION + ")");

  gearnvh::app::CheckOptions check;
  CLI::App* check_cmd = app.add_subcommand(
      "check",
      "Load and validate gearbox files; print derived geometry (radii, centre distance, "
      "contact ratio, mesh frequency).");
  check_cmd->add_option("FILE", check.files, "Gearbox YAML files")->required();
  check_cmd->add_flag("--json", check.json,
                      "Print one JSON document (a list of documents for several files)");

  gearnvh::app::SimulateOptions simulate;
  CLI::App* simulate_cmd = app.add_subcommand(
      "simulate",
      "Run one operating point through the exact piecewise-LTI solver; print the solver summary, "
      "TE and mesh-force statistics.");
  simulate_cmd->add_option("FILE", simulate.file, "Gearbox YAML file")->required();
  AddTierOption(simulate_cmd, simulate.tier,
                "Modal tier: 1..5, \"N40 full\", \"N20 simple\", \"N20 MTA\" "
                "(default: analysis.tier)");
  CheckRange(
      simulate_cmd->add_option("--cycles", simulate.cycles,
                               "Recorded mesh cycles, at most 1000000 (default: analysis.cycles)"),
      1L, gearnvh::GearboxLimits::kMaxRecordedCycles);
  CheckRange(
      simulate_cmd->add_option("--transient", simulate.transient,
                               "Unrecorded mesh cycles first (default: analysis.transient_cycles)"),
      0L, 100000000L);
  simulate_cmd->add_option("--out", simulate.out,
                           "Write trajectory.csv, events.csv and results.json into this directory");
  simulate_cmd->add_option(
      "--uff", simulate.uff,
      "Write TE and mesh force histories and the TE spectrum as UFF dataset 58");
  simulate_cmd->add_flag("--json", simulate.json, "Print the results as one JSON document");
  simulate_cmd->add_flag("--allow-slow", simulate.allow_slow,
                         "Gear trains: run even when the run-cost estimate exceeds one hour "
                         "(refused otherwise; docs/cli.md, \"Run cost\")");
  AddMethodOption(simulate_cmd, simulate.method,
                  "Event location and fusion: v1 (dyadic bisection on dense propagators, a "
                  "baseline), v2 (sub-step certificate + Taylor-polynomial search), v3 "
                  "(closed-form spectral location per segment), fused (default: v3 plus "
                  "segment-run fusion, certified constant-contact cycles and O(1) jumps)");
  CheckRange(simulate_cmd->add_option(
                 "--lyapunov", simulate.lyapunov,
                 "Gear trains: also estimate the K largest Lyapunov exponents (exact tangents "
                 "with saltation per gap, free rotation removed; a second run of the same "
                 "cycles)"),
             1, 64);

  gearnvh::app::ValidateOptions validate;
  CLI::App* validate_cmd = app.add_subcommand(
      "validate",
      "Run the validation ladder on a gearbox: fused vs stepped propagation, exact vs CVODE "
      "reference, closed forms, segment convergence, MTA compliance, ISO 6336 stiffness. "
      "Exit 1 if any check fails.");
  validate_cmd->add_option("FILE", validate.file, "Gearbox YAML file")->required();
  validate_cmd->add_flag(
      "--json", validate.json,
      "Print {name, file, pass, checks: [{name, value, threshold, pass, skipped, detail}]}");
  validate_cmd->add_flag("--allow-slow", validate.allow_slow,
                         "Gear trains: run even when the ladder's run-cost estimate exceeds one "
                         "hour (refused otherwise; docs/cli.md, \"Run cost\")");

  gearnvh::app::SweepOptions sweep;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep",
      "Speed sweep over analysis.speed_sweep: Campbell data of the linearised tier (modes tracked "
      "by MAC, order lines, critical speeds) and a waterfall of steady-state TE spectra (one exact "
      "run per speed, speeds in parallel).");
  sweep_cmd->add_option("FILE", sweep.file, "Gearbox YAML file")->required();
  AddTierOption(sweep_cmd, sweep.tier);
  CheckRange(sweep_cmd->add_option("--cycles", sweep.cycles,
                                   "Recorded mesh cycles per speed (default 512)"),
             2L, 100000000L);
  CheckRange(sweep_cmd->add_option("--transient", sweep.transient,
                                   "Unrecorded cycles per speed (default 200)"),
             0L, 100000000L);
  AddJobsOption(sweep_cmd, sweep.jobs);
  AddMethodOption(sweep_cmd, sweep.method, "v1, v2, v3 or fused (default)");
  sweep_cmd->add_option("--out", sweep.out,
                        "Write campbell.csv, critical_speeds.csv, waterfall.csv and sweep.json (a "
                        "gear train: sweep.json, meshes.csv and loose_gears.csv)");
  sweep_cmd->add_option("--uff", sweep.uff, "Write the TE order tracks as UFF dataset 58");
  sweep_cmd->add_flag("--json", sweep.json, "Print the results as one JSON document");
  sweep_cmd->add_flag("--allow-slow", sweep.allow_slow,
                      "Gear trains: run even when the run-cost estimate exceeds one hour (refused "
                      "otherwise; docs/cli.md, \"Run cost\")");

  gearnvh::app::WhineCommandOptions whine;
  CLI::App* whine_cmd = app.add_subcommand(
      "whine",
      "Whine in the frequency domain over analysis.speed_sweep: every mesh at its mean "
      "stiffness driven by its loaded static TE, runout, pitch errors and the excitation orders; "
      "per line and speed each mesh's dynamic TE and force, each bearing's force on the housing "
      "and each shaft's speed fluctuation, and the speeds where a mesh may lose contact.");
  whine_cmd->add_option("FILE", whine.file, "Gearbox YAML file")->required();
  AddTierOption(whine_cmd, whine.tier);
  CheckRange(whine_cmd->add_option("--speeds", whine.speeds,
                                   "Speeds over analysis.speed_sweep's range (default 2000)"),
             2, 100000);
  CheckRange(whine_cmd->add_option("--harmonics", whine.harmonics,
                                   "Mesh orders 1..H of every mesh (default 3)"),
             1, 20);
  CheckRange(whine_cmd->add_option("--sidebands", whine.sidebands,
                                   "Pitch-error lines +-1..S shaft orders around each mesh order "
                                   "(default 2)"),
             0, 10);
  CheckRange(whine_cmd->add_option("--jobs", whine.jobs, "Threads (default 1; 0: all cores)"), 0,
             1024);
  whine_cmd->add_option("--out", whine.out,
                        "Write whine.json, whine_meshes.csv, whine_bearings.csv and (with "
                        "--housing) whine_housing.csv");
  whine_cmd->add_option("--housing", whine.housing,
                        "Housing transfer table (CSV: frequency_hz,bearing,direction,real,imag): "
                        "the acceleration at its point per line, summed over the bearings");
  whine_cmd->add_option("--uff", whine.uff,
                        "Write every mesh's TE and force tracks as UFF dataset 58");
  whine_cmd->add_flag("--json", whine.json, "Print the results as one JSON document");

  gearnvh::app::AtlasCommandOptions atlas;
  CLI::App* atlas_cmd = app.add_subcommand(
      "atlas",
      "Chaos atlas over two schema parameters (default: analysis.atlas): per cell the largest "
      "Lyapunov exponent, impacts per cycle, rattle index and regime; cells in parallel.");
  atlas_cmd->add_option("FILE", atlas.file, "Gearbox YAML file")->required();
  CheckAxis(atlas_cmd->add_option(
                "--x", atlas.x,
                "x axis PARAMETER=FROM:TO:POINTS, e.g. operating.speed=600rpm:3000rpm:24"),
            "--x", true);
  CheckAxis(atlas_cmd->add_option("--y", atlas.y, "y axis, e.g. operating.torque=0.05Nm:5Nm:24"),
            "--y", true);
  AddTierOption(atlas_cmd, atlas.tier);
  CheckRange(atlas_cmd->add_option("--cycles", atlas.cycles,
                                   "Averaged mesh cycles per cell (default 1080)"),
             8L, 100000000L);
  CheckRange(atlas_cmd->add_option("--transient", atlas.transient,
                                   "Settling cycles per cell (default 300)"),
             0L, 100000000L);
  AddJobsOption(atlas_cmd, atlas.jobs);
  AddMethodOption(atlas_cmd, atlas.method, "Event location v1, v2 or v3 (default; fused means v3)");
  atlas_cmd->add_option("--out", atlas.out, "Write atlas.csv and atlas.json");
  atlas_cmd->add_flag("--json", atlas.json, "Print the atlas as one JSON document");
  atlas_cmd->add_flag("--allow-slow", atlas.allow_slow,
                      "Gear trains: run even when the run-cost estimate exceeds one hour (refused "
                      "otherwise; docs/cli.md, \"Run cost\")");
  atlas_cmd->add_flag("--resume", atlas.resume,
                      "Skip cells already computed by an earlier run of the same command (the "
                      "checkpoint in --out DIR)");

  gearnvh::app::OrbitsCommandOptions orbits;
  CLI::App* orbits_cmd = app.add_subcommand(
      "orbits",
      "Periodic orbits by Newton shooting on the exact cycle map: Floquet multipliers, stability "
      "and the nearest stability boundary (fold, flip, Neimark-Sacker, grazing), at the file's "
      "operating point or continued along one parameter.");
  orbits_cmd->add_option("FILE", orbits.file, "Gearbox YAML file")->required();
  CheckRange(
      orbits_cmd->add_option("--period", orbits.period,
                             "Period in base periods (mesh and excitation both repeat), default 1"),
      1, gearnvh::app::kMaxOrbitPeriod);
  CheckAxis(orbits_cmd->add_option("--sweep", orbits.sweep,
                                   "Continue along PARAMETER=FROM:TO:POINTS, e.g. "
                                   "operating.torque=0.1Nm:1Nm:10"),
            "--sweep");
  AddTierOption(orbits_cmd, orbits.tier);
  CheckRange(orbits_cmd->add_option(
                 "--transient", orbits.transient,
                 "Settling cycles before the first guess (default: analysis.transient_cycles)"),
             0L, 100000000L);
  AddMethodOption(orbits_cmd, orbits.method,
                  "Event location v1, v2 or v3 (default; fused means v3)");
  orbits_cmd->add_option("--out", orbits.out, "Write orbits.csv and orbits.json");
  orbits_cmd->add_flag("--json", orbits.json, "Print the orbits as one JSON document");
  orbits_cmd->add_flag("--allow-slow", orbits.allow_slow,
                       "Gear trains: run even when the run-cost estimate exceeds one hour (refused "
                       "otherwise; docs/cli.md, \"Run cost\")");

  gearnvh::app::TiersCommandOptions tiers;
  CLI::App* tiers_cmd = app.add_subcommand(
      "tiers",
      "Compare the modal truncation levels side by side: DOF, state dimension, natural frequency "
      "and static compliance errors against the full FE model, TE RMS and rattle index against "
      "the finest tier, and cost (matvec and µs per cycle, real-time ratio).");
  tiers_cmd->add_option("FILE", tiers.file, "Gearbox YAML file")->required();
  CheckRange(
      tiers_cmd->add_option("--cycles", tiers.cycles,
                            "Recorded mesh cycles per tier (default min(analysis.cycles, 400))"),
      1L, 100000000L);
  CheckRange(tiers_cmd->add_option(
                 "--transient", tiers.transient,
                 "Unrecorded cycles per tier (default min(analysis.transient_cycles, 200))"),
             0L, 100000000L);
  tiers_cmd->add_option("--out", tiers.out, "Write tiers.json, tiers.csv and tiers.png");
  tiers_cmd->add_flag("--json", tiers.json, "Print the comparison as one JSON document");
  tiers_cmd->add_flag("--allow-slow", tiers.allow_slow,
                      "Gear trains: run even when the run-cost estimate exceeds one hour (refused "
                      "otherwise; docs/cli.md, \"Run cost\")");
#ifdef GEARNVH_HAVE_RENDER
  AddImageSizeOptions(tiers_cmd, tiers.width, tiers.height, tiers.dpi, "tiers.png");
#endif

#ifdef GEARNVH_HAVE_RENDER
  gearnvh::app::ReportCommandOptions report;
  CLI::App* report_cmd = app.add_subcommand(
      "report",
      "Batch NVH report: per gearbox a folder with index.html (tables and images), results.json, "
      "CSV and PNGs (Campbell, waterfall, spectrum with sidebands, TE trace, mesh stiffness, load "
      "sharing, LSTE, phase portrait, atlas heat maps); DIR/index.html compares the batch.");
  report_cmd->add_option("FILE", report.files, "Gearbox YAML files")->required();
  report_cmd
      ->add_option("--out", report.out,
                   "Report folder: new, empty or an earlier gearnvh report (its gearbox folders "
                   "are replaced one by one, only by gearboxes that succeed)")
      ->required();
  AddJobsOption(report_cmd, report.jobs, "Gearboxes in parallel (default: all cores)");
  AddImageSizeOptions(report_cmd, report.width, report.height, report.dpi, "Image");
  bool no_atlas = false;
  report_cmd->add_flag("--no-atlas", no_atlas, "Skip the coarse chaos atlas");
  report_cmd->add_flag("--allow-slow", report.allow_slow,
                       "Gear trains: run even when the run-cost estimate exceeds one hour (refused "
                       "otherwise; docs/cli.md, \"Run cost\")");
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::string message = e.what();
    // A mistyped command or an unknown option before any command: CLI11 only says that a
    // subcommand is required.
    if (app.get_subcommands().empty() && argc > 1) {
      std::vector<std::string> commands;
      for (const CLI::App* c : app.get_subcommands({})) commands.push_back(c->get_name());
      if (argv[1][0] == '-') {
        message = std::string("unknown option '") + argv[1] +
                  "' (before a command only --help and --version); commands: ";
      } else {
        const std::string close = gearnvh::config::ClosestMatch(argv[1], commands);
        message = std::string("unknown command '") + argv[1] + "'" +
                  (close.empty() ? "" : " (did you mean " + close + "?)") + "; commands: ";
      }
      for (size_t i = 0; i < commands.size(); ++i) message += (i > 0 ? ", " : "") + commands[i];
    }
    std::cerr << "error: " << message << "\nRun with --help for more information.\n";
    return gearnvh::app::kExitUsage;
  }
  // Under mpirun only the commands that split their work across ranks run on every rank; for the
  // others rank 0 does everything and the other ranks leave at once.
  bool splits = atlas_cmd->parsed() || sweep_cmd->parsed();
#ifdef GEARNVH_HAVE_RENDER
  splits = splits || report_cmd->parsed();
#endif
  if (gearnvh::app::MpiContext::Rank() != 0 && !splits) return 0;
  try {
    if (check_cmd->parsed()) return gearnvh::app::RunCheck(check);
    if (simulate_cmd->parsed()) return gearnvh::app::RunSimulate(simulate);
    if (validate_cmd->parsed()) return gearnvh::app::RunValidate(validate);
    if (sweep_cmd->parsed()) return gearnvh::app::RunSweep(sweep);
    if (whine_cmd->parsed()) return gearnvh::app::RunWhineCommand(whine);
    if (atlas_cmd->parsed()) return gearnvh::app::RunAtlas(atlas);
    if (orbits_cmd->parsed()) return gearnvh::app::RunOrbits(orbits);
    if (tiers_cmd->parsed()) return gearnvh::app::RunTiers(tiers);
#ifdef GEARNVH_HAVE_RENDER
    if (report_cmd->parsed()) {
      report.atlas = !no_atlas;
      return gearnvh::app::RunReport(report);
    }
#endif
  } catch (const gearnvh::app::IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return gearnvh::app::kExitIo;
  } catch (const std::bad_alloc&) {
    // Not a bug: the run asked for more memory than the process may have (ulimit -v, the machine).
    std::cerr << "error: out of memory: this run needs more memory than the process can get; "
                 "fewer recorded --cycles (32 samples of each are kept), fewer --jobs or fewer "
                 "atlas cells need less\n";
    return gearnvh::app::kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return gearnvh::app::kExitInternal;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  gearnvh::app::InstallSignalCleanup();  // before any thread starts
  gearnvh::app::MpiContext::Initialize(&argc, &argv);
  if (gearnvh::app::MpiContext::Rank() != 0) {
    // Rank 0 alone talks to the user; the others report through it.
    if (std::freopen("/dev/null", "w", stdout) == nullptr ||
        std::freopen("/dev/null", "w", stderr) == nullptr) {
      return 3;
    }
  }
  const int code = Main(argc, argv);
  gearnvh::app::MpiContext::Finalize();
  return code;
}
