// libFuzzer target for the YAML gearbox loader and the model builders: any byte string must either
// load into a valid GearboxSpec whose pair geometry and component model (mesh stiffness over the
// cycle, load sharing, LSTE, FE matrices) are finite, or throw gearnvh::InputError — never crash,
// hang, leak, throw anything else or produce a NaN.
// Build and run: bash scripts/fuzz.sh [seconds]   (see docs/fuzzing.md). Crashes found become
// regression inputs in tests/fuzz/regressions/ (replayed by app_tests).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"

namespace {

void RequireFinite(double v) {
  if (!std::isfinite(v)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const gearnvh::GearboxSpec spec = gearnvh::config::LoadGearboxFromString(text, "fuzz");
    const gearnvh::PairGeometry g = gearnvh::ComputePairGeometry(spec);
    RequireFinite(g.contact_ratio);
    RequireFinite(g.center_distance);
    const gearnvh::ComponentModel model = gearnvh::BuildComponentModel(spec);
    const gearnvh::MeshStiffnessSummary& k = model.mesh_summary;
    for (double v : {k.mean, k.min, k.max, k.lste_peak_to_peak, k.load_sharing_max}) {
      RequireFinite(v);
    }
    if (!model.K.coeffs().allFinite() || !model.M.coeffs().allFinite()) std::abort();
  } catch (const gearnvh::InputError&) {
  }
  return 0;
}
