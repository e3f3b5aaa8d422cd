#include "gearnvh/analysis/train_atlas.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "gearnvh/analysis/parallel_for.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"

namespace gearnvh {

int TrainAtlasResult::Failed() const {
  int failed = 0;
  for (const TrainAtlasCell& c : cells) failed += c.point.ok ? 0 : 1;
  return failed;
}

std::vector<std::string> MeshNames(const TrainSpec& spec) {
  std::vector<std::string> names;
  for (const TrainMesh& m : spec.meshes) names.push_back(m.Name());
  return names;
}

std::vector<std::string> LooseGearNames(const TrainSpec& spec) {
  std::vector<std::string> names;
  for (const TrainGear& g : spec.gears) {
    if (g.mounting == Mounting::kLoose) names.push_back(g.name);
  }
  return names;
}

TrainAtlasResult RunTrainAtlas(const TrainSpec& base, const AtlasAxis& x, const AtlasAxis& y,
                               const TrainAtlasOptions& options, int threads,
                               const AtlasProgress& progress, const std::vector<bool>& skip,
                               const TrainAtlasCellCallback& on_cell) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  TrainAtlasResult r;
  r.x = x;
  r.y = y;
  r.mesh_names = MeshNames(base);
  r.loose_gear_names = LooseGearNames(base);
  const int nx = x.range.points, total = nx * y.range.points;
  if (!skip.empty() && static_cast<int>(skip.size()) != total) {
    throw std::invalid_argument("RunTrainAtlas: skip must have one entry per cell");
  }
  r.cells.resize(static_cast<size_t>(total));
  std::vector<size_t> to_do;
  for (size_t k = 0; k < r.cells.size(); ++k) {
    TrainAtlasCell& c = r.cells[k];
    c.ix = static_cast<int>(k) % nx;
    c.iy = static_cast<int>(k) / nx;
    c.x = AxisValue(x, c.ix);
    c.y = AxisValue(y, c.iy);
    if (!skip.empty() && skip[k]) {
      c.point.message = "skipped";
    } else {
      to_do.push_back(k);
    }
  }
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  r.threads = std::max(
      1, std::min(threads > 0 ? threads : hardware, std::max(1, static_cast<int>(to_do.size()))));
  // Input speed and excitation amplitudes leave a train's meshes as they are (GearTrainAtSpeed):
  // the cells that differ only in those share their meshes, built once (by whichever cell comes
  // first) and moved to each cell, which gives the bits BuildGearTrain gives there. The mesh
  // models were most of a short cell's cost.
  auto changes_meshes = [](const AtlasAxis& axis) {
    const std::optional<TrainParameter> p = TrainParameterOf(axis.parameter);
    return p != TrainParameter::kSpeed && p != TrainParameter::kExcitationAmplitude;
  };
  const bool x_meshes = changes_meshes(x), y_meshes = changes_meshes(y);
  const size_t groups = x_meshes && y_meshes ? 0
                                             : static_cast<size_t>(x_meshes ? nx : 1) *
                                                   (y_meshes ? y.range.points : 1);
  std::vector<std::once_flag> group_built(groups);
  std::vector<GearTrain> group_train(groups);
  SweepProgressCounter counter(static_cast<int>(to_do.size()), progress);
  std::mutex completed;
  ParallelFor(to_do.size(), r.threads, [&](size_t i) {
    TrainAtlasCell& c = r.cells[to_do[i]];
    if (options.cancel != nullptr && options.cancel->load()) {
      c.point.message = "cancelled";
      counter.Tick();
      return;
    }
    // The variant itself may fail (ComputeTrainAtlasPoint never throws).
    try {
      TrainSpec variant = base;
      SetTrainParameter(variant, x.parameter, c.x, "x");
      SetTrainParameter(variant, y.parameter, c.y, "y");
      ValidateTrainSpec(variant);
      TrainBuilder build;
      if (groups > 0) {
        const auto g = static_cast<size_t>(x_meshes ? c.ix : 0) +
                       static_cast<size_t>(y_meshes ? c.iy : 0) * (x_meshes ? nx : 1);
        build = [&, g](const TrainSpec& at) {
          std::call_once(group_built[g], [&] { group_train[g] = BuildGearTrain(at); });
          return GearTrainAtSpeed(group_train[g], at);
        };
      }
      c.point = ComputeTrainAtlasPoint(variant, options, build);
    } catch (const InputError& e) {
      c.point.ok = false;
      c.point.message =
          options.input_error_message
              ? options.input_error_message(e, {{x.parameter, c.x}, {y.parameter, c.y}})
              : e.what();
    } catch (const std::exception& e) {
      c.point.ok = false;
      c.point.message = e.what();
    }
    if (on_cell) {
      const std::lock_guard<std::mutex> lock(completed);
      on_cell(c);
    }
    counter.Tick();
  });
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace gearnvh
