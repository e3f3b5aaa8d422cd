// What an atlas (a pair's or a train's) shows on the terminal: the regime map, the progress line,
// and the failed-cell verdict.
#pragma once

#include <cstddef>
#include <functional>

#include "gearnvh/nvh/atlas.h"

namespace gearnvh::app {

// '.' no impact, 'S' single-sided, 'D' double-sided, 'C' chaotic, 'X' failed.
char RegimeLetter(bool ok, RattleRegime regime);
// The legend (when asked) and the map, rows from the last y value down; letter(k) of cell
// k = iy * nx + ix.
void PrintRegimeMap(int nx, int ny, const std::function<char(int)>& letter, bool legend = true);
// "atlas: 42% (5/12 cells)" on stderr when it is a terminal (and rank 0); empty otherwise.
AtlasProgress AtlasTerminalProgress(int rank, int ranks);
// The exit code of an atlas with `failed` of `total` cells failed: 1 (saying so on stderr) or 0.
int ReportFailedAtlasCells(int failed, size_t total);

}  // namespace gearnvh::app
