// The housing transfer table of `whine --housing FILE` (docs/cli.md, "whine"): CSV with the header
// `frequency_hz,bearing,direction,real,imag`, a row per frequency, bearing and direction; the
// bearing named as whine names it ("input.bearings[0]", "output support"), the direction x, y or
// z, and the complex acceleration at the response point per unit bearing force, (m/s^2)/N. Blank
// lines and lines starting with '#' are skipped; each bearing and direction's rows ascend in
// frequency. Read into analysis/whine.h's HousingTransfer (its Validate checks the curves).
#pragma once

#include <string>

#include "gearnvh/analysis/whine.h"

namespace gearnvh::app {

// Throws InputError naming the file, the line, the column and the rule.
HousingTransfer ReadHousingTable(const std::string& path);

}  // namespace gearnvh::app
