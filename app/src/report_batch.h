// The batch side of a report: the index page comparing the gearboxes, the earlier report kept in
// DIR, and the transfer of a rank's finished gearboxes to rank 0 under MPI.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "report_gearbox.h"

namespace gearnvh::app {

// The file that marks a folder as a gearnvh report (its presence allows writing into it).
inline constexpr const char* kReportMarker = ".gearnvh-report";

// DIR/index.html: one row per gearbox (failed ones with their error).
std::string BatchIndex(const std::vector<GearboxEntry>& entries);

// The gearboxes of an earlier report in `dir` (its report.json), empty when there is none.
std::vector<GearboxEntry> EarlierEntries(const std::filesystem::path& dir);

// A rank's finished gearboxes (`indices` into `entries`, their folders under `root`) for rank 0:
// a JSON header (entries and file names) followed by the files' bytes, each preceded by its size
// (8 bytes). UnpackEntries fills `entries` and writes the folders under `staging`.
std::string PackEntries(const std::vector<size_t>& indices,
                        const std::vector<GearboxEntry>& entries,
                        const std::filesystem::path& root);
void UnpackEntries(const std::string& packed, std::vector<GearboxEntry>& entries,
                   const std::filesystem::path& staging);

}  // namespace gearnvh::app
