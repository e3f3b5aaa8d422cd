// A bundled example with some of its text replaced: the end-to-end tests run the examples'
// code paths on shorter analyses (fewer speeds, cells or cycles), which the sanitizer build needs
// to stay inside the CI budget (docs/testing.md).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh::testing {

struct TextEdit {
  std::string from;
  std::string to;
};

// The example's text with each edit's `from` (which must occur) replaced once by its `to`.
inline std::string ExampleVariantText(const std::string& example,
                                      const std::vector<TextEdit>& edits) {
  std::string text = ReadWholeFile(kExamples + "/" + example);
  for (const TextEdit& e : edits) {
    const size_t at = text.find(e.from);
    if (at == std::string::npos)
      throw std::logic_error(example + " no longer contains '" + e.from + "'");
    text.replace(at, e.from.size(), e.to);
  }
  return text;
}

// The same, written under the example's own file name in the test's folder (commands name their
// outputs after the file: `report` writes idle_rattle.yaml's page to idle-rattle/).
inline std::filesystem::path WriteExampleVariant(const TempDir& dir, const std::string& example,
                                                 const std::vector<TextEdit>& edits) {
  return dir.Write(example, ExampleVariantText(example, edits));
}

// examples/flexible_shafts.yaml's operating point moved to the preprint's strong-rattle point
// (7548 rpm, 20 N m, order 15.5 of 2e5 rad/s^2): at tiers 2 and 3 the rattle grows without bound
// and a run stops out of range after ~130 cycles (tests/solver/out_of_range_test.cc); tier 1, 4
// and the N20/N40 tiers stay bounded. Further edits (an analysis section) may follow.
inline const TextEdit kStrongRattlePoint = {
    "  speed: 3000 rpm\n  torque: 200 N*m\n",
    "  speed: 7548.387097 rpm\n  torque: 20 N*m\n  excitation:\n"
    "    - {order: 15.5, amplitude: 200000 rad/s^2, phase: 0 deg}\n"};

// With kStrongRattlePoint, a sweep at tier 2 whose 6000 rpm run stops out of range (at cycle
// ~46) while 5000 and 5500 rpm finish (double-sided rattle): evenly spaced, one speed failed.
inline const TextEdit kStrongRattleSweep = {
    "  speed_sweep: {from: 500 rpm, to: 9000 rpm, points: 35}",
    "  speed_sweep: {from: 5000 rpm, to: 6000 rpm, points: 3}"};

}  // namespace gearnvh::testing
