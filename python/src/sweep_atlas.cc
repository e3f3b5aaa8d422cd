// gearnvh.sweep and gearnvh.atlas: the library calls behind `gearnvh sweep` and `gearnvh atlas`,
// with per-speed series and atlas grids as NumPy views of the C++ results.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "atlas_command.h"
#include "atlas_documents.h"
#include "binding_support.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "gearbox.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/exact_solver.h"
#include "simulate_command.h"
#include "sweep_command.h"
#include "train_command_options.h"

namespace gearnvh::python {

namespace {

struct Sweep {
  gearnvh::SpeedSweepResult result;
  nlohmann::json doc;  // the `sweep --json` document
};

struct Atlas {
  AtlasResult result;
  nlohmann::json doc;  // the `atlas --json` document
};

std::shared_ptr<Sweep> RunSweep(const Gearbox& gb, const py::object& tier,
                                std::optional<long> cycles, std::optional<long> transient, int jobs,
                                const std::string& method, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  const Tier chosen = TierArgument(tier, spec.analysis.tier, source);
  gearnvh::SpeedSweepOptions options;
  options.cycles = cycles.value_or(options.cycles);
  options.transient_cycles = transient.value_or(options.transient_cycles);
  options.waterfall_cycles = std::min(options.waterfall_cycles, options.cycles - 1);
  options.threads = jobs;
  options.method = NamingSource(source, [&] { return app::ParseMethod(method, "method"); });
  NamingSource(source, [&] {
    app::RequireCycleCounts(options.cycles, 2, options.transient_cycles, OptionNames{""});
    RequirePairRunLength(spec, spec.analysis.speed_sweep.from, options.cycles,
                         options.transient_cycles, cycles, transient, false);
  });
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] {
          options.cancel = &control.cancel;
          const ComponentModel model = BuildComponentModel(spec);
          const ReducedModel reduced = ReduceModel(model, chosen);
          auto out = std::make_shared<Sweep>();
          out->result = gearnvh::RunSpeedSweep(spec, model, reduced, options,
                                               [&](int d, int t) { control.Progress(d, t); });
          out->doc = app::SweepJson(out->result, spec.pinion.teeth);
          out->doc["name"] = spec.name;
          out->doc["file"] = source;
          out->doc["tier"] = reduced.name;
          out->doc["cycles_per_speed"] = options.cycles;
          out->doc["transient_cycles"] = options.transient_cycles;
          return out;
        });
      },
      progress);
}

std::shared_ptr<Atlas> RunAtlas(const Gearbox& gb, const std::optional<std::string>& x,
                                const std::optional<std::string>& y, const py::object& tier,
                                std::optional<long> cycles, std::optional<long> transient, int jobs,
                                const std::string& method, const py::object& progress) {
  const GearboxSpec spec = gb.spec();
  const std::string source = gb.source();
  AtlasOptions options;
  options.input_error_message = app::UserWording(kKeywordInputNames, app::PairAxisValueText(spec));
  options.tier = TierArgument(tier, spec.analysis.tier, source);
  options.cycles = cycles.value_or(options.cycles);
  options.transient_cycles = transient.value_or(options.transient_cycles);
  options.threads = jobs;
  options.events =
      EventMethodOf(NamingSource(source, [&] { return app::ParseMethod(method, "method"); }));
  std::optional<AtlasAxis> ax = spec.analysis.atlas_x, ay = spec.analysis.atlas_y;
  if (x) ax = config::ParseAxisOption(*x, "x");
  if (y) ay = config::ParseAxisOption(*y, "y");
  if (!ax || !ay) {
    throw InputError("analysis.atlas", 0, "(missing)",
                     "an atlas needs two axes: analysis.atlas.x and .y in the gearbox, or x= and "
                     "y= ('operating.speed=600rpm:3000rpm:24')",
                     source);
  }
  NamingSource(source, [&] {
    if (x) app::RequirePairAxisOption(spec, *ax, *x, "x");
    if (y) app::RequirePairAxisOption(spec, *ay, *y, "y");
    if (x) app::RequireAtlasAxisRange(*ax, *x, "x");
    if (y) app::RequireAtlasAxisRange(*ay, *y, "y");
    RequirePairRunLength(spec, app::LowestInputSpeed(TrainOf(spec), ax, ay), options.cycles,
                         options.transient_cycles, cycles, transient, false);
  });
  if (ax->parameter == ay->parameter) {
    throw InputError("y", 0, ay->parameter, "must differ from the x parameter", source);
  }
  NamingSource(source, [&] { options.Validate(); });
  return RunInterruptible(
      [&](CallControl& control) {
        options.cancel = &control.cancel;
        auto out = std::make_shared<Atlas>();
        out->result =
            RunChaosAtlas(spec, *ax, *ay, options, [&](int d, int t) { control.Progress(d, t); });
        options.cancel = nullptr;
        out->doc = app::AtlasJson(out->result, options);
        out->doc["name"] = spec.name;
        out->doc["file"] = source;
        return out;
      },
      progress);
}

template <typename Field>
py::cpp_function SpeedField(Field gearnvh::SpeedPoint::*member) {
  return py::cpp_function([member](py::object self) {
    return StridedView(self.cast<const Sweep&>().result.points, member, self);
  });
}

template <typename Field>
py::cpp_function CellGrid(Field AtlasCell::*member) {
  return py::cpp_function([member](py::object self) {
    const AtlasResult& r = self.cast<const Atlas&>().result;
    return GridView(r.cells, member, r.y.range.points, r.x.range.points, self);
  });
}

}  // namespace

void BindSweepAtlas(py::module_& m) {
  py::class_<Sweep, std::shared_ptr<Sweep>>(
      m, "Sweep",
      "Speed sweep (gearnvh sweep): Campbell data and a waterfall, one exact run per speed. "
      "Per-speed attributes are read-only NumPy views.")
      .def_property_readonly("speeds_rpm", SpeedField(&gearnvh::SpeedPoint::speed_rpm))
      .def_property_readonly("speeds_rad_s", SpeedField(&gearnvh::SpeedPoint::speed_rad_s))
      .def_property_readonly("te_rms", SpeedField(&gearnvh::SpeedPoint::te_rms), "m per speed")
      .def_property_readonly("te_peak_to_peak", SpeedField(&gearnvh::SpeedPoint::te_peak_to_peak))
      .def_property_readonly("events_per_cycle", SpeedField(&gearnvh::SpeedPoint::events_per_cycle))
      .def_property_readonly("ok",
                             [](const Sweep& s) {
                               std::vector<bool> ok;
                               for (const auto& p : s.result.points) ok.push_back(p.ok);
                               return ok;
                             })
      .def_property_readonly("regimes",
                             [](const Sweep& s) {
                               std::vector<std::string> r;
                               for (const auto& p : s.result.points)
                                 r.push_back(p.ok ? RattleRegimeName(p.regime) : "");
                               return r;
                             })
      .def_property_readonly(
          "order_step", [](const Sweep& s) { return s.result.order_step; },
          "pinion orders per waterfall bin")
      .def_property_readonly(
          "orders",
          [](const Sweep& s) {
            py::array_t<double> o(s.result.order_bins);
            for (int k = 0; k < s.result.order_bins; ++k) o.mutable_at(k) = k * s.result.order_step;
            return o;
          },
          "pinion order of each waterfall bin")
      .def_property_readonly(
          "waterfall",
          [](const Sweep& s) {
            std::vector<std::vector<double>> rows;
            for (const auto& p : s.result.points) rows.push_back(p.amplitude_m);
            return Matrix(rows);
          },
          "TE amplitude, m: (speeds, order bins)")
      .def_property_readonly(
          "campbell_hz", [](const Sweep& s) { return Matrix(s.result.campbell.frequency_hz); },
          "natural frequency of each tracked mode, Hz: (modes, speeds); NaN where not found")
      .def_property_readonly(
          "campbell_damping",
          [](const Sweep& s) { return Matrix(s.result.campbell.damping_ratio); }, "(modes, speeds)")
      .def_property_readonly("campbell_mac",
                             [](const Sweep& s) { return Matrix(s.result.campbell.mac); })
      .def_property_readonly("mode_labels",
                             [](const Sweep& s) {
                               std::vector<std::string> labels;
                               for (const ModeInfo& i : s.result.campbell.modes)
                                 labels.push_back(i.Label());
                               return labels;
                             })
      .def_property_readonly(
          "critical_speeds",
          [](const Sweep& s) { return ToPython(s.doc["campbell"]["critical_speeds"]); },
          "list of {order, mode, mode_label, speed_rpm, frequency_hz}")
      .def(
          "to_dict", [](const Sweep& s) { return ToPython(s.doc); },
          "The document `gearnvh sweep --json` prints.")
      .def("__repr__", [](const Sweep& s) {
        const auto& p = s.result.points;
        const int failed = s.result.failed();
        return fmt::format(
            "<gearnvh.Sweep {} speeds{}, {} tracked modes, {} failed>", p.size(),
            p.empty() ? std::string()
                      : fmt::format(" {:.4g}-{:.4g} rpm", p.front().speed_rpm, p.back().speed_rpm),
            s.result.campbell.modes.size(), failed);
      });

  py::class_<Atlas, std::shared_ptr<Atlas>>(
      m, "Atlas",
      "Chaos atlas (gearnvh atlas). Grids have shape (len(y), len(x)) and are read-only NumPy "
      "views of the cells.")
      .def_property_readonly("x_parameter", [](const Atlas& a) { return a.result.x.parameter; })
      .def_property_readonly("y_parameter", [](const Atlas& a) { return a.result.y.parameter; })
      .def_property_readonly(
          "x", [](const Atlas& a) { return AxisValues(a.result.x); }, "SI")
      .def_property_readonly(
          "y", [](const Atlas& a) { return AxisValues(a.result.y); }, "SI")
      .def_property_readonly("lyapunov_per_s", CellGrid(&AtlasCell::lyapunov_per_s))
      .def_property_readonly("lyapunov_per_forcing_cycle",
                             CellGrid(&AtlasCell::lyapunov_per_forcing_cycle))
      .def_property_readonly("lyapunov_standard_error",
                             CellGrid(&AtlasCell::lyapunov_standard_error))
      .def_property_readonly("drive_impacts_per_cycle",
                             CellGrid(&AtlasCell::drive_impacts_per_cycle))
      .def_property_readonly("back_impacts_per_cycle", CellGrid(&AtlasCell::back_impacts_per_cycle))
      .def_property_readonly("rattle_index", CellGrid(&AtlasCell::rattle_index),
                             "impact energy per forcing cycle, J")
      .def_property_readonly("impact_velocity_rms", CellGrid(&AtlasCell::impact_velocity_rms))
      .def_property_readonly("separation_fraction", CellGrid(&AtlasCell::separation_fraction))
      .def_property_readonly("regime",
                             [](const Atlas& a) {
                               std::vector<std::vector<std::string>> grid(
                                   static_cast<size_t>(a.result.y.range.points));
                               for (const AtlasCell& c : a.result.cells) {
                                 grid[static_cast<size_t>(c.iy)].push_back(
                                     c.ok ? RattleRegimeName(c.regime) : "failed");
                               }
                               return grid;
                             })
      .def_property_readonly("failed", [](const Atlas& a) { return a.result.Failed(); })
      .def(
          "to_dict", [](const Atlas& a) { return ToPython(a.doc); },
          "The document `gearnvh atlas --json` prints.")
      .def("__repr__", [](const Atlas& a) {
        return fmt::format("<gearnvh.Atlas {} x {}: {} x {} cells, {} failed>",
                           a.result.x.parameter, a.result.y.parameter, a.result.x.range.points,
                           a.result.y.range.points, a.result.Failed());
      });

  m.def("sweep", &RunSweep, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("cycles") = py::none(), py::arg("transient") = py::none(), py::arg("jobs") = 0,
        py::arg("method") = "fused", py::arg("progress") = py::none(),
        "Speed sweep over analysis.speed_sweep, as `gearnvh sweep` (cycles default 512, "
        "transient 200, jobs 0 = all cores).");
  m.def("atlas", &RunAtlas, py::arg("gearbox"), py::kw_only(), py::arg("x") = py::none(),
        py::arg("y") = py::none(), py::arg("tier") = py::none(), py::arg("cycles") = py::none(),
        py::arg("transient") = py::none(), py::arg("jobs") = 0, py::arg("method") = "v3",
        py::arg("progress") = py::none(),
        "Chaos atlas over two parameters, as `gearnvh atlas`: x, y like "
        "'operating.speed=600rpm:3000rpm:24' (default analysis.atlas).");
}

}  // namespace gearnvh::python
