#include "report_batch.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "atomic_file.h"
#include "display_units.h"
#include "report_html.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

std::string ReadWholeFileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// Sizes in the packed stream: 8 bytes, native order (the ranks run on one kind of machine).
void AppendSize(std::string& out, uint64_t n) { out.append(reinterpret_cast<const char*>(&n), 8); }
uint64_t ReadSize(const std::string& in, size_t& at) {
  uint64_t n = 0;
  std::memcpy(&n, in.data() + at, 8);
  at += 8;
  return n;
}

// A gear train's summary lists `key` per mesh ("in-l0 0.12<br>l5-o5 0.034"); a pair's has it once
// (`num`: the pair's cell of a key, "-" when missing).
template <typename Num>
std::string PerMesh(const nlohmann::json& s, const char* key, const Num& num) {
  const auto meshes = s.find("meshes");
  if (meshes == s.end() || !meshes->is_array()) return num(key);
  std::string cell;
  for (const nlohmann::json& m : *meshes) {
    const auto name = m.find("name");
    const auto value = m.find(key);
    if (!cell.empty()) cell += "<br>";
    cell += (name != m.end() && name->is_string() ? Html(name->get<std::string>()) : "-") + " " +
            (value != m.end() && value->is_number() ? Number(value->get<double>()) : "-");
  }
  return cell.empty() ? "-" : cell;
}

// A pair's rattle regime; a train's loudest loose gear with its impact energy per second, or "no
// loose gear impacts" ("-" for a train without loose gears).
template <typename Text>
std::string Rattle(const nlohmann::json& s, const Text& text) {
  const auto gear = s.find("loudest_loose_gear");
  if (gear == s.end()) return text("regime");
  if (!gear->is_string()) {
    const auto count = s.find("loose_gears");
    return count != s.end() && count->is_number() && count->get<double>() > 0
               ? "no loose gear impacts"
               : "-";
  }
  const auto energy = s.find("loudest_loose_gear_impact_energy_per_second_w");
  return Html(gear->get<std::string>()) +
         (energy != s.end() && energy->is_number()
              ? " (" + Number(energy->get<double>() * 1e3) + " mW of impacts)"
              : std::string());
}

}  // namespace

std::string BatchIndex(const std::vector<GearboxEntry>& entries) {
  std::ostringstream h;
  int failed = 0;
  for (const GearboxEntry& e : entries) failed += e.ok ? 0 : 1;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>gearnvh "
       "report</title>\n"
    << kReportStyle << "\n</head><body>\n<h1>gearnvh report</h1>\n<p>"
    << Count(static_cast<long>(entries.size()), "gearbox", "gearboxes") << ", "
    << (failed == 0 ? "<span class=\"ok\">all complete</span>"
                    : fmt::format("<span class=\"warn\">{} failed</span>", failed))
    << "</p>\n<table>\n<tr><th>gearbox</th><th>modal model</th><th>speed</th><th>torque"
       "</th><th>TE RMS (µm)</th><th>rattle regime / loudest loose gear</th><th>impacts / mesh "
       "cycle</th><th>accel. ratio</th><th>first critical speed (rpm)</th><th>chaotic atlas "
       "cells</th><th>real-time ratio</th></tr>\n";
  for (const GearboxEntry& e : entries) {
    if (!e.ok) {
      h << "<tr><td>" << Html(e.file)
        << "</td><td colspan=\"10\" class=\"warn\">failed: " << Html(e.error);
      if (e.earlier_kept) {
        h << " (the result of an earlier run is kept: <a href=\"" << e.folder << "/index.html\">"
          << Html(e.folder) << "</a>)";
      }
      h << "</td></tr>\n";
      continue;
    }
    // An earlier run's summary may lack keys (older versions): a missing key reads as "-".
    const nlohmann::json& s = e.summary;
    auto text = [&s](const char* key) {
      const auto it = s.find(key);
      return it != s.end() && it->is_string() ? Html(it->get<std::string>()) : std::string("-");
    };
    auto num = [&s](const char* key) {
      const auto it = s.find(key);
      return it != s.end() && it->is_number() ? Number(it->get<double>()) : std::string("-");
    };
    h << "<tr><td><a href=\"" << e.folder << "/index.html\">" << Html(e.name) << "</a>"
      << (e.from_earlier ? " (earlier run)" : "") << "</td><td>" << text("tier") << "</td><td>"
      << text("speed") << "</td><td>" << text("torque") << "</td><td>"
      << PerMesh(s, "te_rms_um", num) << "</td><td>" << Rattle(s, text) << "</td><td>"
      << PerMesh(s, "impacts_per_cycle", num) << "</td><td>" << num("acceleration_ratio")
      << "</td><td>" << num("first_critical_speed_rpm") << "</td><td>" << num("chaotic_atlas_cells")
      << "</td><td>" << num("real_time_ratio") << "</td></tr>\n";
  }
  h << "</table>\n" << kImageCheckScript << "\n</body></html>\n";
  return h.str();
}

std::string PackEntries(const std::vector<size_t>& indices,
                        const std::vector<GearboxEntry>& entries, const fs::path& root) {
  nlohmann::json header = nlohmann::json::array();
  std::string blobs;
  for (size_t i : indices) {
    const GearboxEntry& e = entries[i];
    nlohmann::json files = nlohmann::json::array();
    if (e.ok) {
      for (const auto& f : fs::directory_iterator(root / e.folder)) {
        const std::string bytes = ReadWholeFileBytes(f.path());
        files.push_back(f.path().filename().string());
        AppendSize(blobs, bytes.size());
        blobs += bytes;
      }
    }
    header.push_back({{"index", i},
                      {"file", e.file},
                      {"folder", e.folder},
                      {"name", e.name},
                      {"ok", e.ok},
                      {"error", e.error},
                      {"io_reason", e.io_reason},
                      {"summary", e.summary},
                      {"wall_s", e.wall_s},
                      {"files", files}});
  }
  const std::string text = header.dump();
  std::string out;
  AppendSize(out, text.size());
  out += text;
  out += blobs;
  return out;
}

void UnpackEntries(const std::string& packed, std::vector<GearboxEntry>& entries,
                   const fs::path& staging) {
  size_t at = 0;
  const uint64_t length = ReadSize(packed, at);
  const nlohmann::json header = nlohmann::json::parse(packed.substr(at, length));
  at += length;
  for (const auto& h : header) {
    GearboxEntry& e = entries[h.at("index").get<size_t>()];
    e.file = h.at("file").get<std::string>();
    e.folder = h.at("folder").get<std::string>();
    e.name = h.at("name").get<std::string>();
    e.ok = h.at("ok").get<bool>();
    e.error = h.at("error").get<std::string>();
    e.io_reason = h.at("io_reason").get<std::string>();
    e.summary = h.at("summary");
    e.wall_s = h.at("wall_s").get<double>();
    if (!e.ok) continue;
    fs::create_directories(staging / e.folder);
    for (const auto& name : h.at("files")) {
      const uint64_t size = ReadSize(packed, at);
      WriteFileAtomically((staging / e.folder / name.get<std::string>()).string(),
                          packed.substr(at, size));
      at += size;
    }
  }
}

// The gearboxes of an earlier report in `dir` (its report.json), empty when there is none.
std::vector<GearboxEntry> EarlierEntries(const fs::path& dir) {
  std::vector<GearboxEntry> out;
  if (!fs::exists(dir / kReportMarker) || !fs::exists(dir / "report.json")) return out;
  try {
    const nlohmann::json doc = nlohmann::json::parse(ReadWholeFileBytes(dir / "report.json"));
    for (const auto& g : doc.at("gearboxes")) {
      GearboxEntry e;
      e.file = g.at("file").get<std::string>();
      e.folder = g.at("folder").get<std::string>();
      e.name = g.at("name").get<std::string>();
      e.ok = g.at("ok").get<bool>();
      e.summary = g.at("summary");
      e.wall_s = g.at("wall_s").get<double>();
      if (e.ok && !e.folder.empty() && fs::is_directory(dir / e.folder)) out.push_back(e);
    }
  } catch (const std::exception&) {
    // An unreadable earlier index: its gearbox folders stay, unlisted.
  }
  return out;
}

}  // namespace gearnvh::app
