// libFuzzer target for the YAML gearbox loader: any byte string must either load into a valid
// GearboxSpec or throw gearnvh::InputError — never crash, hang, leak or throw anything else.
// Build and run: bash scripts/fuzz.sh [seconds]   (see docs/fuzzing.md)
#include <cstddef>
#include <cstdint>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const gearnvh::GearboxSpec spec = gearnvh::config::LoadGearboxFromString(text, "fuzz");
    // A spec that loads must also give finite geometry.
    (void)gearnvh::ComputePairGeometry(spec);
  } catch (const gearnvh::InputError&) {
  }
  return 0;
}
