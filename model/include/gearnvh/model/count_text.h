// Counts in messages with the noun in the right number ("1 entry", "2 entries").
#pragma once

#include <string>

namespace gearnvh {

// "1 gearbox", "3 gearboxes": `count` and the singular or plural noun.
inline std::string Count(long count, const std::string& singular, const std::string& plural) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural);
}

}  // namespace gearnvh
