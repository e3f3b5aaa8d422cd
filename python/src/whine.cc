// gearnvh.whine on a gear pair or a gear train: the frequency-domain whine behind `gearnvh whine
// FILE` (analysis/whine.h), its tracks as NumPy arrays and to_dict() giving the command line's
// JSON.
#include "gearnvh/analysis/whine.h"

#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>

#include "binding_support.h"
#include "gearbox.h"
#include "housing_table.h"
#include "train_call.h"
#include "train_command_options.h"
#include "whine_command.h"

namespace gearnvh::python {

namespace {

struct WhineRun {
  WhineResult result;
  nlohmann::json doc;  // the `whine --json` document

  size_t MeshIndex(const py::object& mesh) const {
    if (py::isinstance<py::int_>(mesh)) {
      const long i = mesh.cast<long>();
      if (i >= 0 && i < static_cast<long>(result.meshes.size())) return static_cast<size_t>(i);
    } else if (py::isinstance<py::str>(mesh)) {
      const std::string name = mesh.cast<std::string>();
      for (size_t i = 0; i < result.meshes.size(); ++i) {
        if (result.meshes[i].name == name) return i;
      }
    }
    throw py::key_error(fmt::format("no mesh {} (meshes: {})", py::str(mesh).cast<std::string>(),
                                    doc["meshes"].size()));
  }
};

// The keywords as C++ values: read on the calling thread, which holds the GIL.
struct WhineKeywords {
  std::optional<std::string> tier;
  int speeds, harmonics, sidebands, jobs;
  std::optional<HousingTransfer> housing;
};

std::shared_ptr<WhineRun> RunOn(const TrainSpec& spec, const std::string& source,
                                const WhineKeywords& k, CallControl& control) {
  WhineOptions options;
  options.tier =
      app::CheckTrainCommandOptions(k.tier, spec, LadderMethod::kFused, kKeywordNames).tier;
  options.speeds = k.speeds;
  options.mesh_harmonics = k.harmonics;
  options.sideband_orders = k.sidebands;
  options.threads = k.jobs;
  options.housing = k.housing;
  options.cancel = &control.cancel;
  options.names = kKeywordNames;
  auto out = std::make_shared<WhineRun>();
  out->result = RunWhine(spec, options, [&](int d, int t) { control.Progress(d, t); });
  out->doc = app::WhineJson(out->result);
  out->doc["name"] = spec.name;
  out->doc["file"] = source;
  out->doc["input_shaft"] = spec.operating.input_shaft;
  return out;
}

template <typename Model>
std::shared_ptr<WhineRun> WhineOf(const Model& model, const py::object& tier, int speeds,
                                  int harmonics, int sidebands, int jobs,
                                  const std::optional<std::string>& housing,
                                  const py::object& progress) {
  const WhineKeywords k{
      TierText(tier),
      speeds,
      harmonics,
      sidebands,
      jobs,
      housing ? std::optional<HousingTransfer>(app::ReadHousingTable(*housing)) : std::nullopt};
  return RunOnModel(
      model,
      [&k](const auto& spec, const std::string& source, CallControl& control) {
        if constexpr (std::is_same_v<std::decay_t<decltype(spec)>, GearboxSpec>) {
          return RunOn(TrainOf(spec), source, k, control);
        } else {
          return RunOn(spec, source, k, control);
        }
      },
      progress);
}

constexpr const char* kWhineDoc =
    "Whine in the frequency domain, as `gearnvh whine FILE`: every mesh at its mean stiffness "
    "driven by its loaded static TE, runout, pitch errors and the excitation orders, at `speeds` "
    "speeds over analysis.speed_sweep. tier: None (analysis.tier), 1..5 or a tier's name; "
    "harmonics: mesh orders 1..H; sidebands: pitch-error lines +-1..S shaft orders; jobs: "
    "threads (0: all cores); housing: a transfer table's path (CSV, as --housing).";

}  // namespace

void BindWhine(py::module_& m) {
  py::class_<WhineRun, std::shared_ptr<WhineRun>>(
      m, "Whine", "Frequency-domain whine of a gearbox (gearnvh whine).")
      .def_property_readonly(
          "speeds_rpm",
          [](const WhineRun& w) {
            return py::array_t<double>(py::cast(w.doc["speeds_rpm"].get<std::vector<double>>()));
          })
      .def_property_readonly(
          "orders",
          [](const WhineRun& w) {
            std::vector<double> orders;
            for (const WhineLine& l : w.result.lines) orders.push_back(l.order);
            return py::array_t<double>(py::cast(orders));
          },
          "Each line's order of the input shaft.")
      .def_property_readonly("labels",
                             [](const WhineRun& w) {
                               std::vector<std::string> labels;
                               for (const WhineLine& l : w.result.lines) labels.push_back(l.label);
                               return labels;
                             })
      .def_property_readonly("meshes",
                             [](const WhineRun& w) {
                               std::vector<std::string> names;
                               for (const WhineMesh& mesh : w.result.meshes)
                                 names.push_back(mesh.name);
                               return names;
                             })
      .def(
          "te_amplitude_m",
          [](const WhineRun& w, const py::object& mesh) {
            return Matrix(w.result.meshes[w.MeshIndex(mesh)].te_amplitude_m);
          },
          py::arg("mesh") = 0,
          "Lines x speeds: the dynamic TE amplitude of a mesh (name or index).")
      .def(
          "force_amplitude_n",
          [](const WhineRun& w, const py::object& mesh) {
            return Matrix(w.result.meshes[w.MeshIndex(mesh)].force_amplitude_n);
          },
          py::arg("mesh") = 0, "Lines x speeds: the mesh force amplitude of a mesh.")
      .def(
          "contact_loss",
          [](const WhineRun& w, const py::object& mesh) {
            const std::vector<bool>& flags = w.result.meshes[w.MeshIndex(mesh)].contact_loss;
            return py::array_t<bool>(py::cast(flags));
          },
          py::arg("mesh") = 0, "Per speed: the mesh may lose contact (the mean model fails).")
      .def(
          "to_dict", [](const WhineRun& w) { return ToPython(w.doc); },
          "The document `gearnvh whine --json` prints (bearing forces and shaft speeds too).")
      .def("__repr__", [](const WhineRun& w) {
        return fmt::format(
            "<gearnvh.Whine {}: {} meshes, {} lines, {} speeds, {} may lose contact>",
            TierName(w.result.tier), w.result.meshes.size(), w.result.lines.size(),
            w.result.speed_rad_s.size(), w.result.ContactLossSpeeds());
      });
  m.def("whine", &WhineOf<Train>, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("speeds") = 2000, py::arg("harmonics") = 3, py::arg("sidebands") = 2,
        py::arg("jobs") = 1, py::arg("housing") = py::none(), py::arg("progress") = py::none(),
        kWhineDoc);
  m.def("whine", &WhineOf<Gearbox>, py::arg("gearbox"), py::kw_only(), py::arg("tier") = py::none(),
        py::arg("speeds") = 2000, py::arg("harmonics") = 3, py::arg("sidebands") = 2,
        py::arg("jobs") = 1, py::arg("housing") = py::none(), py::arg("progress") = py::none(),
        kWhineDoc);
}

}  // namespace gearnvh::python
