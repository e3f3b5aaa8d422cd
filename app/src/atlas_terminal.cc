#include "atlas_terminal.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>

namespace gearnvh::app {

char RegimeLetter(bool ok, RattleRegime regime) {
  if (!ok) return 'X';
  switch (regime) {
    case RattleRegime::kNoImpact:
      return '.';
    case RattleRegime::kSingleSided:
      return 'S';
    case RattleRegime::kDoubleSided:
      return 'D';
    case RattleRegime::kChaotic:
      return 'C';
  }
  return '?';
}

void PrintRegimeMap(int nx, int ny, const std::function<char(int)>& letter, bool legend) {
  if (legend) fmt::print("  . no impact  S single-sided  D double-sided  C chaotic  X failed\n");
  for (int iy = ny - 1; iy >= 0; --iy) {
    std::string row;
    for (int ix = 0; ix < nx; ++ix) row += letter(iy * nx + ix);
    fmt::print("  {}\n", row);
  }
}

int ReportFailedAtlasCells(int failed, size_t total) {
  if (failed == 0) return 0;
  std::cerr << "error: " << failed << " of " << total
            << " atlas cells failed (listed in the output)\n";
  return 1;
}

AtlasProgress AtlasTerminalProgress(int rank, int ranks) {
  if (rank != 0 || ::isatty(STDERR_FILENO) == 0) return {};
  return [ranks](int done, int todo) {
    fmt::print(stderr, "\ratlas: {:3d}% ({}/{} cells{})", 100 * done / std::max(todo, 1), done,
               todo, ranks > 1 ? fmt::format(" on rank 0 of {}", ranks) : "");
  };
}

}  // namespace gearnvh::app
