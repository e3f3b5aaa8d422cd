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

}  // namespace gearnvh::testing
