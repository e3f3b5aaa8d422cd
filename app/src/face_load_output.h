// The load across a mesh's face (FaceLoad) in `check`'s text and JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/mesh_stiffness.h"

namespace gearnvh::app {

// Lines (each ending in a newline, indented by `indent`) for a mesh whose face is misaligned or
// modified; empty otherwise.
std::string FaceLoadText(const FaceLoad& face, const std::string& indent);

// {"misalignment": {manufacturing, shafts, lead_slopes, linear}, "factor", "iso_6336_method_c",
// "loaded_width", "face_width", "position", "line_load", "mismatch"} (SI: m, N/m).
nlohmann::json FaceLoadJson(const FaceLoad& face);

}  // namespace gearnvh::app
