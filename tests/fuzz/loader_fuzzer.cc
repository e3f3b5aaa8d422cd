// libFuzzer target for the YAML gearbox loader and the model builders of both schemas: any byte
// string must either load into a spec whose models are finite or throw gearnvh::InputError — never
// crash, hang, leak, throw anything else or produce a NaN (the contract: fuzz_contract.h).
// Build and run: bash scripts/fuzz.sh [seconds]   (see docs/fuzzing.md). Crashes found become
// regression inputs in tests/fuzz/regressions/ (replayed by app_tests).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_contract.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // Anything but InputError escapes and is reported by libFuzzer as a crash.
  gearnvh::fuzz::CheckInput(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
  return 0;
}
