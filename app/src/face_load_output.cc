#include "face_load_output.h"

#include <fmt/format.h>

#include <cmath>

namespace gearnvh::app {
namespace {

const char* ModelName(FaceLoad::Model model) {
  switch (model) {
    case FaceLoad::Model::kModelled:
      return "modelled";
    case FaceLoad::Model::kUnloaded:
      return "unloaded";
    case FaceLoad::Model::kOverridden:
      return "overridden";
    case FaceLoad::Model::kUniform:
      break;
  }
  return "uniform";
}

}  // namespace

std::string FaceLoadText(const FaceLoad& face, const std::string& indent) {
  if (!face.misaligned()) return "";
  std::string out;
  const auto line = [&](const std::string& name, const std::string& value) {
    out += fmt::format("{}{:<34}{:>12}\n", indent, name, value);
  };
  // Below the last digit shown: 0.000, not rounding's -0.000.
  const auto um = [](double m) {
    return fmt::format("{:.3f} µm", std::abs(m) < 5e-10 ? 0.0 : m * 1e6);
  };
  out += indent + "load across the face (drive flank, mesh-cycle mean):\n";
  line("  misalignment f_ma", um(face.manufacturing_misalignment));
  line("  from the shafts' deflection f_sh", um(face.shaft_misalignment));
  line("  lead slopes", um(face.lead_slopes));
  line("  linear mismatch F_βy", um(face.linear_mismatch));
  if (face.model == FaceLoad::Model::kUniform) {
    out += indent + "  (the mismatch cancels: the load is uniform, K_Hβ 1)\n";
    return out;
  }
  if (!face.modelled()) {
    out += indent + "  (not applied: see the warning)\n";
    return out;
  }
  line("  K_Hβ (slice model)", fmt::format("{:.4f}", face.factor));
  line("  K_Hβ (ISO 6336-1 formula at F_βy)", fmt::format("{:.4f}", face.iso_method_c));
  line("  loaded width (narrowest)", fmt::format("{:.2f} mm", face.loaded_width * 1e3));
  line("  face width", fmt::format("{:.2f} mm", face.face_width * 1e3));
  // The distribution at ~11 points across the face, start to end.
  std::string positions, loads;
  const size_t n = face.position.size();
  const size_t step = n > 11 ? (n - 1) / 10 : 1;
  for (size_t i = 0; i < n; i += step) {
    positions += fmt::format("{:>8.1f}", face.position[i] * 1e3);
    loads += fmt::format("{:>8.1f}", face.line_load[i] * 1e-3);
  }
  out += indent + fmt::format("  {:<22}{}\n", "position [mm]", positions);
  out += indent + fmt::format("  {:<22}{}\n", "line load [N/mm]", loads);
  return out;
}

nlohmann::json FaceLoadJson(const FaceLoad& face) {
  return {{"misalignment",
           {{"manufacturing", face.manufacturing_misalignment},
            {"shafts", face.shaft_misalignment},
            {"lead_slopes", face.lead_slopes},
            {"linear", face.linear_mismatch}}},
          {"modelled", face.modelled()},
          {"model", ModelName(face.model)},
          {"factor", face.factor},
          {"iso_6336_method_c", face.iso_method_c},
          {"loaded_width", face.loaded_width},
          {"face_width", face.face_width},
          {"position", face.position},
          {"line_load", face.line_load},
          {"mismatch", face.mismatch}};
}

}  // namespace gearnvh::app
