// How a caller names its options in the messages of the analysis layer's errors: the analysis
// never names a command-line flag or a keyword itself.
#pragma once

#include <algorithm>
#include <string>

namespace gearnvh {

// How the caller names its options in messages: "--cycles" on the command line, "cycles" for
// the Python module's keyword (OptionNames{""}).
struct OptionNames {
  std::string prefix = "--";
  // A keyword spells a dashed option with underscores ("allow-slow" -> "allow_slow").
  std::string operator()(const std::string& option) const {
    std::string name = option;
    if (prefix.empty()) std::replace(name.begin(), name.end(), '-', '_');
    return prefix + name;
  }
};

}  // namespace gearnvh
