#include "check_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "face_load_output.h"
#include "finite_results.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/segment_tables.h"
#include "train_check.h"

namespace gearnvh::app {
std::vector<ReducedModel> ReduceAvailableTiers(const ComponentModel& model) {
  const std::vector<Tier> all{Tier::kTier1, Tier::kTier2,     Tier::kTier3, Tier::kTier4,
                              Tier::kTier5, Tier::kN20Simple, Tier::kN20Mta};
  std::vector<ReducedModel> out;
  for (Tier t : all) {
    if (TierAvailable(model, t)) out.push_back(ReduceModel(model, t));
  }
  return out;
}

namespace {

// A stiffness zone's mean, null when the mesh cycle has no such zone (a helical mesh never
// carried by one pair alone): the model reports those as 0.
nlohmann::json ZoneMean(double mean) {
  return mean > 0.0 ? nlohmann::json(mean) : nlohmann::json();
}

nlohmann::json RadiiJson(const GearRadii& r) {
  return {{"pitch_radius", r.pitch},
          {"base_radius", r.base},
          {"tip_radius", r.tip},
          {"root_radius", r.root}};
}

void PrintText(const std::string& file, const GearboxSpec& spec, const ComponentModel& model,
               const ModalSummary& modes, const std::vector<ReducedModel>& tiers) {
  const PairGeometry& g = model.geometry;
  constexpr double kMm = 1e3;
  fmt::print("{}  ({})\n", spec.name, file);
  fmt::print("  {:<28}{:>14}{:>14}\n", "geometry [mm]", "pinion", "wheel");
  fmt::print("  {:<28}{:>14d}{:>14d}\n", "teeth", spec.pinion.teeth, spec.wheel.teeth);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "pitch radius", g.pinion.pitch * kMm,
             g.wheel.pitch * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "base radius", g.pinion.base * kMm,
             g.wheel.base * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "tip radius", g.pinion.tip * kMm, g.wheel.tip * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "root radius", g.pinion.root * kMm,
             g.wheel.root * kMm);
  fmt::print("  {:<28}{:>14.4f} mm\n", "centre distance", g.center_distance * kMm);
  fmt::print("  {:<28}{:>14.4f} °\n", "working pressure angle",
             g.working_pressure_angle * 180.0 / 3.141592653589793);
  fmt::print("  {:<28}{:>14.6f}\n", "contact ratio", g.contact_ratio);
  fmt::print("  {:<28}{:>14.3f} Hz\n", "mesh frequency", g.mesh_frequency_hz);
  fmt::print("  {:<28}{:>14.3f} µs\n", "mesh period", g.mesh_period_s * 1e6);
  const MeshStiffnessSummary& k = model.mesh_summary;
  fmt::print("  mesh stiffness at {:.4g} N along the line of action ({}){}\n", model.cycle.load,
             TorqueText(spec),
             model.cycle.overridden ? " (user override)" : " (potential energy method)");
  fmt::print("  {:<28}{:>14.4g} N/m\n", "mean", k.mean);
  fmt::print("  {:<28}{:>14.4g} N/m\n", "min", k.min);
  fmt::print("  {:<28}{:>14.4g} N/m\n", "max", k.max);
  // A helical mesh may never carry on one pair (or on exactly two) alone: no such zone, no mean.
  for (const auto& [name, mean] : {std::pair{"single-pair mean", k.single_pair_mean},
                                   std::pair{"double-pair mean", k.double_pair_mean}}) {
    if (mean > 0.0) {
      fmt::print("  {:<28}{:>14.4g} N/m\n", name, mean);
    } else {
      fmt::print("  {:<28}{:>14} (no such zone in the mesh cycle)\n", name, "n/a");
    }
  }
  fmt::print("  {:<28}{:>14.4f} µm\n", "LSTE peak-to-peak", k.lste_peak_to_peak * 1e6);
  fmt::print("  {:<28}{:>14.4f}\n", "max load share", k.load_sharing_max);
  fmt::print("{}", FaceLoadText(model.cycle.face, "  "));
  fmt::print("  finite elements: {} nodes, {} DOF{}, {}\n", model.nodes.size(), model.dofs,
             model.flexible ? " (flexible shafts)" : " (rigid shafts on bearings)",
             Count(modes.rigid_body_modes, "rigid-body mode", "rigid-body modes"));
  fmt::print("  {:<28}", "natural frequencies [Hz]");
  for (size_t i = 0; i < modes.frequencies_hz.size(); ++i) {
    if (i > 0 && i % 5 == 0) fmt::print("\n  {:<28}", "");
    fmt::print("{:>10.1f}", modes.frequencies_hz[i]);
  }
  fmt::print("\n");
  fmt::print("  {:<12}{:>5}{:>7}{:>6}{:>14}{:>12}   lowest natural frequencies [Hz]\n",
             "modal tier", "DOF", "state", "rigid", "g_mesh [m/N]", "vs full");
  for (const ReducedModel& r : tiers) {
    fmt::print("  {:<12}{:>5}{:>7}{:>6}{:>14.4e}{:>11}  ", r.name, r.dof,
               StateDimension(model, r, spec.operating.excitation), r.rigid_body_modes,
               r.static_mesh_compliance,
               ComplianceErrorText(ComplianceErrorVsFull(r.tier, r.compliance_error_vs_full)));
    for (size_t i = 0; i < std::min<size_t>(4, r.natural_frequencies_hz.size()); ++i) {
      fmt::print("{:>9.1f}", r.natural_frequencies_hz[i]);
    }
    fmt::print("\n");
  }
  for (const std::string& w : model.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace

std::optional<double> ComplianceErrorVsFull(Tier tier, double error) {
  return tier == Tier::kTier1 ? std::nullopt : std::optional<double>(error);
}

nlohmann::json ComplianceErrorJson(std::optional<double> error) {
  return error ? nlohmann::json(*error) : nlohmann::json();
}

std::string ComplianceErrorText(std::optional<double> error) {
  return error ? fmt::format("{:.2e}", *error) : "n/a";
}

nlohmann::json CheckReport(const GearboxSpec& spec, const ComponentModel& model,
                           const ModalSummary& modes, const std::vector<ReducedModel>& tiers) {
  const PairGeometry& g = model.geometry;
  nlohmann::json doc;
  doc["name"] = spec.name;
  doc["geometry"] = {{"contact_ratio", g.contact_ratio},
                     {"center_distance", g.center_distance},
                     {"working_pressure_angle", g.working_pressure_angle},
                     {"base_pitch", g.base_pitch},
                     {"mesh_frequency_hz", g.mesh_frequency_hz},
                     {"mesh_period_s", g.mesh_period_s},
                     {"gear_ratio", g.gear_ratio},
                     {"pinion", RadiiJson(g.pinion)},
                     {"wheel", RadiiJson(g.wheel)}};
  const MeshStiffnessSummary& k = model.mesh_summary;
  doc["mesh"] = {{"contact_ratio", k.contact_ratio},
                 {"load", model.cycle.load},
                 {"stiffness_model", model.cycle.overridden ? "override" : "potential_energy"},
                 {"stiffness",
                  {{"mean", k.mean},
                   {"min", k.min},
                   {"max", k.max},
                   {"single_pair_mean", ZoneMean(k.single_pair_mean)},
                   {"double_pair_mean", ZoneMean(k.double_pair_mean)}}},
                 {"lste_peak_to_peak", k.lste_peak_to_peak},
                 {"load_sharing_max", k.load_sharing_max},
                 {"face_load", FaceLoadJson(model.cycle.face)},
                 {"segments", model.segmentation.segments.size()},
                 {"mesh_damping", model.mesh_damping},
                 {"warnings", model.warnings}};
  doc["fe"] = {{"nodes", model.nodes.size()},
               {"dofs", model.dofs},
               {"flexible_shafts", model.flexible},
               {"rigid_body_modes", modes.rigid_body_modes},
               {"natural_frequencies_hz", modes.frequencies_hz}};
  doc["tiers"] = nlohmann::json::array();
  std::vector<std::string> unavailable;
  for (Tier t : kAllTiers) {
    if (!TierAvailable(model, t)) unavailable.emplace_back(TierName(t));
  }
  for (const ReducedModel& r : tiers) {
    doc["tiers"].push_back(
        {{"name", r.name},
         {"dof", r.dof},
         {"state_dim", StateDimension(model, r, spec.operating.excitation)},
         {"rigid_body_modes", r.rigid_body_modes},
         {"natural_frequencies_hz", r.natural_frequencies_hz},
         {"static_mesh_compliance", r.static_mesh_compliance},
         {"compliance_error_vs_full",
          ComplianceErrorJson(ComplianceErrorVsFull(r.tier, r.compliance_error_vs_full))}});
  }
  doc["tiers_unavailable"] = unavailable;
  doc["full_static_mesh_compliance"] =
      tiers.empty() ? 0.0 : tiers.front().full_static_mesh_compliance;
  return doc;
}

int RunCheck(const CheckOptions& options) {
  int exit_code = 0;
  nlohmann::json documents = nlohmann::json::array();
  for (const std::string& file : options.files) {
    config::SourceLocations where;
    try {
      const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(file);
      where = loaded.locations;
      if (loaded.schema == 2) {
        const TrainCheck check = BuildTrainCheck(loaded.train);
        nlohmann::json doc = TrainCheckReport(loaded.train, check);
        doc["tier"] = TierName(loaded.train.analysis.tier);  // as the pair's document
        RequireFinite(doc, "check");
        if (options.json) {
          doc["file"] = file;
          documents.push_back(std::move(doc));
        } else {
          PrintTrainCheck(file, loaded.train, check);
        }
        continue;
      }
      const GearboxSpec& spec = *loaded.pair;
      const ComponentModel model = BuildComponentModel(spec);
      RequireTierAvailable(model, spec.analysis.tier);  // as simulate, sweep and report do
      const ModalSummary modes = FullModelFrequencies(model, kReportedModes);
      const std::vector<ReducedModel> tiers = ReduceAvailableTiers(model);
      nlohmann::json doc = CheckReport(spec, model, modes, tiers);
      RequireFinite(doc, "check");
      if (options.json) {
        doc["file"] = file;
        documents.push_back(std::move(doc));
      } else {
        PrintText(file, spec, model, modes, tiers);
      }
    } catch (const InputError& e) {
      // Errors raised below the loader (e.g. segments_per_cycle too small) carry no file name.
      const std::string message = InputErrorMessage(e, file, where);
      std::cerr << "error: " << message << "\n";
      exit_code = std::max(exit_code, static_cast<int>(kExitInput));
      if (options.json) documents.push_back({{"file", file}, {"error", message}});
    } catch (const std::exception& e) {
      // A bug (or a non-finite result) in one file: that file's verdict is 3, the others go on.
      const std::string message = file + ": " + e.what();
      std::cerr << "internal error: " << message << "\n";
      exit_code = std::max(exit_code, static_cast<int>(kExitInternal));
      if (options.json) documents.push_back({{"file", file}, {"internal_error", message}});
    }
  }
  if (options.json) {
    // One file: its document. Several: a list of documents, in the order given.
    const nlohmann::json& out = documents.size() == 1 ? documents[0] : documents;
    if (!(documents.size() == 1 && exit_code != 0)) std::cout << out.dump(2) << "\n";
  }
  return exit_code;
}

}  // namespace gearnvh::app
