// Shared pieces of the gearnvh Python module: long calls off the GIL with Ctrl-C and progress,
// zero-copy NumPy views into C++ results, JSON documents as Python objects, argument parsing.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <future>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/nvh/atlas.h"
#include "simulate_command.h"

namespace gearnvh::python {

namespace py = pybind11;

// What a long call shares with the thread that waits for it.
struct CallControl {
  std::atomic<bool> cancel{false};
  std::atomic<long> done{0}, total{0};
  void Progress(long d, long t) {
    total.store(t);
    done.store(d);
  }
};

// Runs work(control) on a worker thread with the GIL released. The calling thread wakes every
// 50 ms: it runs Python's signal handlers (Ctrl-C raises KeyboardInterrupt: the work is told to
// stop through control.cancel, joined, and the exception propagates) and calls `progress(done,
// total)` when it is a Python callable and the count moved (and once more at the end when the
// last count was not shown). The work's own exception is rethrown here.
template <typename Work>
auto RunInterruptible(Work&& work, const py::object& progress)
    -> decltype(work(std::declval<CallControl&>())) {
  using Result = decltype(work(std::declval<CallControl&>()));
  CallControl control;
  std::packaged_task<Result()> task([&] { return work(control); });
  std::future<Result> result = task.get_future();
  bool interrupted = false;
  long shown = -1;
  {
    py::gil_scoped_release release;
    std::thread worker(std::move(task));
    while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        interrupted = true;
        control.cancel.store(true);
        break;
      }
      const long done = control.done.load();
      if (!progress.is_none() && done != shown && control.total.load() > 0) {
        shown = done;
        try {
          progress(done, control.total.load());
        } catch (py::error_already_set&) {
          // An exception in the callback stops the work like Ctrl-C and is raised after it.
          control.cancel.store(true);
          worker.join();
          throw;
        }
      }
    }
    worker.join();
  }
  if (interrupted) throw py::error_already_set();  // the KeyboardInterrupt of the handler
  Result out = result.get();
  if (!progress.is_none() && control.total.load() > 0 && control.done.load() != shown) {
    progress(control.done.load(), control.total.load());
  }
  return out;
}

// The NumPy element type of a field: enums as their underlying integer.
template <typename Field, bool = std::is_enum_v<Field>>
struct Element {
  using type = Field;
};
template <typename Field>
struct Element<Field, true> {
  using type = std::underlying_type_t<Field>;
};

// f(row) for every row, as a list: for per-row values a NumPy view cannot hold (a method's flag,
// strings).
template <typename Row, typename F>
auto PerRow(const std::vector<Row>& rows, F f) {
  std::vector<std::decay_t<decltype(f(std::declval<const Row&>()))>> out;
  out.reserve(rows.size());
  for (const Row& r : rows) out.push_back(f(r));
  return out;
}

// A read-only 1-D NumPy view of `member` across a vector of structs (no copy); `owner` keeps the
// memory alive.
template <typename Struct, typename Field>
py::array StridedView(const std::vector<Struct>& rows, const Field Struct::*member,
                      const py::handle& owner) {
  const Struct probe{};
  const auto offset =
      reinterpret_cast<const char*>(&(probe.*member)) - reinterpret_cast<const char*>(&probe);
  const char* base = rows.empty() ? nullptr : reinterpret_cast<const char*>(rows.data()) + offset;
  py::array view(py::dtype::of<typename Element<Field>::type>(),
                 {static_cast<py::ssize_t>(rows.size())},
                 {static_cast<py::ssize_t>(sizeof(Struct))}, base, owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

// The same over a row-major grid of structs: shape (rows, columns).
template <typename Struct, typename Field>
py::array GridView(const std::vector<Struct>& cells, const Field Struct::*member, long rows,
                   long columns, const py::handle& owner) {
  const Struct probe{};
  const auto offset =
      reinterpret_cast<const char*>(&(probe.*member)) - reinterpret_cast<const char*>(&probe);
  const char* base = cells.empty() ? nullptr : reinterpret_cast<const char*>(cells.data()) + offset;
  const auto cell = static_cast<py::ssize_t>(sizeof(Struct));
  py::array view(py::dtype::of<typename Element<Field>::type>(), {rows, columns},
                 {columns * cell, cell}, base, owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

// A read-only view of a vector of doubles.
inline py::array VectorView(const std::vector<double>& v, const py::handle& owner) {
  py::array view(py::dtype::of<double>(), {static_cast<py::ssize_t>(v.size())},
                 {static_cast<py::ssize_t>(sizeof(double))}, v.data(), owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

// A (rows x columns) array copied from nested vectors (rows of equal length; NaN pads).
py::array_t<double> Matrix(const std::vector<std::vector<double>>& rows);

// A JSON document as Python dicts, lists and numbers (through the json module: exactly what the
// command line prints with --json).
py::object ToPython(const nlohmann::json& doc);

// An atlas axis's values, SI.
py::array_t<double> AxisValues(const AtlasAxis& a);

// tier= : None (the file's analysis.tier), 1..5, or "N40 full", "N20 simple", "N20 MTA".
// InputError naming `tier` and the gearbox's `source` otherwise.
Tier TierArgument(const py::object& tier, Tier fallback, const std::string& source);

// The command line's limits on a pair's counts given as keywords (named `cycles`, `transient`):
// cycles + transient mesh cycles at `lowest_speed` (rad/s) last at most
// GearboxLimits::kMaxSimulatedSeconds of simulated time, and, when every recorded cycle is kept
// in memory (`simulate`), at most GearboxLimits::kMaxRecordedCycles are recorded. InputError
// otherwise (without a source: call it inside NamingSource).
void RequirePairRunLength(const GearboxSpec& spec, double lowest_speed, long cycles, long transient,
                          const std::optional<long>& cycles_keyword,
                          const std::optional<long>& transient_keyword, bool recorded_in_memory);

// tier= on a train: None (analysis.tier) or the text `--tier` takes (the app checks it).
std::optional<std::string> TierText(const py::object& tier);

// Errors name the module's keywords ("cycles"), not the command line's options ("--cycles").
inline const gearnvh::OptionNames kKeywordNames{""};

}  // namespace gearnvh::python
