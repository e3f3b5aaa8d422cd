// `gearnvh report FILE... --out DIR [--jobs N] [--width PX] [--height PX] [--dpi DPI]
// [--no-atlas]`: one folder per gearbox (index.html with the summary tables and the images
// inline, results.json, CSV of the key series, PNGs) and DIR/index.html comparing the batch.
//
// Gearboxes run in parallel (their images are drawn one at a time); a bad file is listed in the
// batch index and makes the exit code 1 while the others complete. The report is built in the
// staging folder of an OutputFolder (output_folder.h) and moved into DIR at the end, gearbox folder
// by gearbox folder: only gearboxes that succeeded replace their earlier folders, a run in which
// every gearbox failed leaves DIR untouched, and a DIR that exists and is not a gearnvh report is
// refused untouched. Under mpirun the gearboxes are split across ranks; rank 0 receives the other
// ranks' files and alone writes.
#pragma once

#include <string>
#include <vector>

namespace gearnvh::app {

struct ReportCommandOptions {
  std::vector<std::string> files;
  std::string out;
  int jobs = 0;  // gearboxes in parallel; 0 = all cores
  int width = 1200, height = 800;
  double dpi = 100.0;
  bool atlas = true;        // a coarse chaos atlas when the gearbox defines analysis.atlas
  bool allow_slow = false;  // gear trains: run even when the cost estimate exceeds an hour
};

int RunReport(const ReportCommandOptions& options);

}  // namespace gearnvh::app
