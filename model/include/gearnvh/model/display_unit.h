// A unit a quantity is shown in to the user (the unit the input wrote it in).
#pragma once

#include <string>

namespace gearnvh {

// Shown value = SI value * per_si.
struct DisplayUnit {
  std::string symbol;
  double per_si = 1.0;
};

}  // namespace gearnvh
