#include "gearnvh/analysis/train_load_warnings.h"

#include <algorithm>

namespace gearnvh {
namespace {

// Shaft names quoted and joined: "'a', 'b'".
std::string Quoted(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) {
    out += out.empty() ? "'" : ", '";
    out += n;
    out += '\'';
  }
  return out;
}

std::vector<std::string> OutputShafts(const TrainSpec& spec, const TrainTopology& t) {
  std::vector<bool> leads_on(t.bodies.size(), false);  // another shaft is reached through it
  for (size_t b = 0; b < t.bodies.size(); ++b) {
    const int parent = t.ParentBody(spec, static_cast<int>(b));
    if (parent < 0 || t.bodies[b].kind != BodyKind::kShaft) continue;
    leads_on[static_cast<size_t>(parent)] = true;
  }
  // Power reaches an output through a gear mesh: a shaft coupled to the input and driving only
  // loose gears (a flywheel ahead of the gearbox input, in neutral) is not the train's output.
  const auto through_mesh = [&](int b) {
    for (; b >= 0; b = t.ParentBody(spec, b)) {
      if (t.parent_mesh[static_cast<size_t>(b)] >= 0) return true;
    }
    return false;
  };
  std::vector<std::string> out;
  for (size_t b = 0; b < t.bodies.size(); ++b) {
    const TrainBody& body = t.bodies[b];
    if (body.kind == BodyKind::kShaft && static_cast<int>(b) != t.input_body && !leads_on[b] &&
        !spec.shafts[static_cast<size_t>(body.shaft)].fixed && through_mesh(static_cast<int>(b))) {
      out.push_back(body.name);
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> TrainLoadWarnings(const TrainSpec& spec, const TrainTopology& topology) {
  const std::vector<TrainLoad>& loads = spec.operating.loads;
  if (loads.empty()) {
    return {
        "operating.loads: the train has no load: every mesh runs at zero mean torque, its "
        "teeth kept in contact only by inertia and the excitation (give the output shaft its "
        "load, and each loose gear its drag)"};
  }
  const std::vector<std::string> outputs = OutputShafts(spec, topology);
  const bool loaded = std::any_of(loads.begin(), loads.end(), [&](const TrainLoad& load) {
    return std::find(outputs.begin(), outputs.end(), load.on) != outputs.end();
  });
  if (loaded || outputs.empty()) return {};
  // Appended rather than chained with operator+ (GCC 12 PR 105651 false -Wrestrict).
  std::string warning = "operating.loads: no load on the output shaft";
  warning += outputs.size() == 1 ? " " : "s ";
  warning += Quoted(outputs);
  warning += " (the end of the train from the input '";
  warning += spec.operating.input_shaft;
  warning +=
      "'): the meshes leading to it carry only the other loads' power (give the output its "
      "load, if it drives one)";
  return {warning};
}

}  // namespace gearnvh
