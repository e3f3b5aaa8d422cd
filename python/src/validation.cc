// gearnvh.validate on a gear train or a gear pair: the validation ladders behind `gearnvh validate
// FILE`, their checks as objects and to_dict() giving the command line's JSON.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

#include "binding_support.h"
#include "gearbox.h"
#include "gearnvh/analysis/train_validation.h"
#include "gearnvh/analysis/validation_ladder.h"
#include "train_call.h"
#include "validate_command.h"

namespace gearnvh::python {

namespace {

struct Validation {
  std::vector<gearnvh::ValidationRow> rows;
  nlohmann::json doc;  // the `validate --json` document
};

std::shared_ptr<Validation> ValidateTrain(const Train& train, bool allow_slow,
                                          const py::object& progress) {
  return RunOnModel(
      train,
      [allow_slow](const TrainSpec& spec, const std::string& source, CallControl& control) {
        auto out = std::make_shared<Validation>();
        gearnvh::TrainValidationOptions options;
        options.cancel = &control.cancel;
        options.progress = [&](int d, int t) { control.Progress(d, t); };
        options.allow_slow = allow_slow;
        options.names = kKeywordNames;
        out->rows = gearnvh::RunTrainValidationLadder(spec, options);
        out->doc = app::ValidationDocument(out->rows, spec.name, source);
        return out;
      },
      progress);
}

// The pair's ladder (`gearnvh validate FILE` on a schema-1 file). It has no progress counts.
std::shared_ptr<Validation> ValidateGearbox(const Gearbox& gearbox, const py::object& progress) {
  return RunOnModel(
      gearbox,
      [](const GearboxSpec& spec, const std::string& source, CallControl& control) {
        auto out = std::make_shared<Validation>();
        out->rows = gearnvh::RunValidationLadder(spec, &control.cancel);
        out->doc = app::ValidationDocument(out->rows, spec.name, source);
        return out;
      },
      progress);
}

}  // namespace

void BindValidation(py::module_& m) {
  // Validation.
  py::class_<gearnvh::ValidationRow>(m, "ValidationCheck", "One row of the validation ladder.")
      .def_readonly("name", &gearnvh::ValidationRow::name)
      .def_readonly("value", &gearnvh::ValidationRow::value)
      .def_readonly("threshold", &gearnvh::ValidationRow::threshold)
      .def_readonly("passed", &gearnvh::ValidationRow::pass, "value <= threshold")
      .def_readonly("skipped", &gearnvh::ValidationRow::skipped)
      .def_readonly("detail", &gearnvh::ValidationRow::detail, "what was compared, or why skipped")
      .def("__repr__", [](const gearnvh::ValidationRow& r) {
        return "<gearnvh.ValidationCheck " + r.name + ": " +
               (r.skipped ? "skipped" : (r.pass ? "pass" : "FAIL")) + ">";
      });
  py::class_<Validation, std::shared_ptr<Validation>>(
      m, "Validation", "The validation ladder of a gearbox (gearnvh validate).")
      .def_readonly("checks", &Validation::rows)
      .def_property_readonly("passed",
                             [](const Validation& v) { return v.doc["pass"].get<bool>(); })
      .def(
          "to_dict", [](const Validation& v) { return ToPython(v.doc); },
          "The document `gearnvh validate --json` prints.")
      .def("__repr__", [](const Validation& v) {
        long passed = 0, skipped = 0;
        for (const gearnvh::ValidationRow& r : v.rows) {
          skipped += r.skipped ? 1 : 0;
          passed += !r.skipped && r.pass ? 1 : 0;
        }
        return fmt::format("<gearnvh.Validation {}: {} of {} checks passed, {} skipped>",
                           v.doc["pass"].get<bool>() ? "pass" : "FAIL", passed,
                           v.rows.size() - static_cast<size_t>(skipped), skipped);
      });

  m.def("validate", &ValidateTrain, py::arg("gearbox"), py::kw_only(),
        py::arg("allow_slow") = false, py::arg("progress") = py::none(),
        "The validation ladder of a gear train, as `gearnvh validate TRAIN.yaml`: the exact "
        "solver against the CVODE reference and its V2 and V1 event methods. allow_slow: run "
        "even when the ladder's run-cost estimate is above an hour (as simulate's).");
  m.def("validate", &ValidateGearbox, py::arg("gearbox"), py::kw_only(),
        py::arg("progress") = py::none(),
        "The validation ladder of a gear pair, as `gearnvh validate FILE`: fused vs stepped "
        "propagation, exact vs CVODE reference, closed forms, segment convergence, MTA "
        "compliance, ISO 6336 stiffness. No progress counts; Ctrl-C interrupts.");
}

}  // namespace gearnvh::python
