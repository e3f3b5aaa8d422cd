#include "check_command.h"

#include <fmt/format.h>

#include <cstdio>
#include <iostream>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::app {
namespace {

nlohmann::json RadiiJson(const GearRadii& r) {
  return {{"pitch_radius", r.pitch},
          {"base_radius", r.base},
          {"tip_radius", r.tip},
          {"root_radius", r.root}};
}

void PrintText(const std::string& file, const GearboxSpec& spec, const PairGeometry& g) {
  constexpr double kMm = 1e3;
  fmt::print("{}  ({})\n", spec.name, file);
  fmt::print("  {:<28}{:>14}{:>14}\n", "geometry [mm]", "pinion", "wheel");
  fmt::print("  {:<28}{:>14d}{:>14d}\n", "teeth", spec.pinion.teeth, spec.wheel.teeth);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "pitch radius", g.pinion.pitch * kMm, g.wheel.pitch * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "base radius", g.pinion.base * kMm, g.wheel.base * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "tip radius", g.pinion.tip * kMm, g.wheel.tip * kMm);
  fmt::print("  {:<28}{:>14.4f}{:>14.4f}\n", "root radius", g.pinion.root * kMm, g.wheel.root * kMm);
  fmt::print("  {:<28}{:>14.4f} mm\n", "centre distance", g.center_distance * kMm);
  fmt::print("  {:<28}{:>14.4f} deg\n", "working pressure angle",
             g.working_pressure_angle * 180.0 / 3.141592653589793);
  fmt::print("  {:<28}{:>14.6f}\n", "contact ratio", g.contact_ratio);
  fmt::print("  {:<28}{:>14.3f} Hz\n", "mesh frequency", g.mesh_frequency_hz);
  fmt::print("  {:<28}{:>14.3f} us\n", "mesh period", g.mesh_period_s * 1e6);
}

}  // namespace

nlohmann::json CheckReport(const GearboxSpec& spec) {
  const PairGeometry g = ComputePairGeometry(spec);
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
  return doc;
}

int RunCheck(const CheckOptions& options) {
  int exit_code = 0;
  nlohmann::json documents = nlohmann::json::array();
  for (const std::string& file : options.files) {
    try {
      const GearboxSpec spec = config::LoadGearboxFile(file);
      nlohmann::json doc = CheckReport(spec);
      if (options.json) {
        doc["file"] = file;
        documents.push_back(std::move(doc));
      } else {
        PrintText(file, spec, ComputePairGeometry(spec));
      }
    } catch (const InputError& e) {
      std::cerr << "error: " << e.what() << "\n";
      exit_code = 1;
      if (options.json) documents.push_back({{"file", file}, {"error", e.what()}});
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
