// The gearnvh Python module: gearboxes from YAML files, YAML strings or dicts; edits by schema
// path; check, simulate, sweep, atlas, orbits and tiers over the same library calls as the command
// line.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding_support.h"
#include "check_command.h"
#include "gearbox.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"
#include "train_call.h"

namespace gearnvh::python {

namespace {

// ascii(o): a str with every character beyond ASCII escaped, a lone surrogate included.
std::string Ascii(const py::handle& o) {
  return py::reinterpret_steal<py::str>(PyObject_ASCII(o.ptr())).cast<std::string>();
}

// A str as UTF-8. A lone surrogate (from a broken decode or surrogateescape) has no UTF-8 form:
// an input error at `path`, where pybind11 would raise a bare cast error.
std::string Utf8(const py::handle& text, const std::string& path) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(text.ptr(), &size);
  if (data != nullptr) return {data, static_cast<size_t>(size)};
  PyErr_Clear();
  throw InputError(path, 0, Ascii(text),
                   "must be text UTF-8 can encode: a lone surrogate such as '\\ud800' cannot be");
}

}  // namespace

config::LoadedGearbox SetByPath(config::GearboxDocument& document, const py::object& path_text,
                                const py::object& value) {
  if (!py::isinstance<py::str>(path_text)) {
    throw py::type_error("gearnvh: set(path, value): path must be a str such as 'mesh.backlash', "
                         "not " +
                         std::string(py::str(path_text.get_type().attr("__name__"))));
  }
  const std::string path = Utf8(path_text, Ascii(path_text));
  if (py::isinstance<py::bool_>(value)) {
    return document.SetScalar(path, value.cast<bool>() ? "true" : "false");
  }
  if (py::isinstance<py::str>(value)) return document.SetScalar(path, Utf8(value, path));
  if (py::isinstance<py::dict>(value) || py::isinstance<py::list>(value) ||
      py::isinstance<py::tuple>(value)) {
    const std::string json = py::str(py::module_::import("json").attr("dumps")(value));
    return document.SetYaml(path, json);
  }
  if (PyIndex_Check(value.ptr()) != 0) {  // int, numpy integers
    return document.SetScalar(path, py::str(py::int_(value)));
  }
  if (PyNumber_Check(value.ptr()) != 0) {  // float, numpy floats: SI, shortest round trip
    return document.SetScalar(path, py::repr(py::float_(value)));
  }
  throw py::type_error("gearnvh: set(" + path +
                       ", value): value must be a str such as '0.3 N*m', a number (SI), a "
                       "bool, a dict or a list, not " +
                       std::string(py::str(value.get_type().attr("__name__"))));
}

namespace {

// A Gearbox for a schema-1 document, a Train for a schema-2 one.
py::object Wrap(config::GearboxDocument document) {
  config::LoadedGearbox loaded = document.Load();
  if (loaded.schema == 2) return py::cast(Train(std::move(document), std::move(loaded.train)));
  return py::cast(Gearbox(std::move(document), std::move(*loaded.pair)));
}

py::object Load(const py::object& source) {
  if (py::isinstance<py::dict>(source)) {
    const std::string json = py::str(py::module_::import("json").attr("dumps")(source));
    return Wrap(config::GearboxDocument::FromData(json, "<dict>"));
  }
  if (py::isinstance<Gearbox>(source)) return py::cast(source.cast<Gearbox>());
  if (py::isinstance<Train>(source)) return py::cast(source.cast<Train>());
  const std::string text = py::str(py::module_::import("os").attr("fspath")(source));
  // YAML text has a line break (or is one flow mapping); anything else is a file name.
  if (text.find('\n') != std::string::npos || text.starts_with('{')) {
    return Wrap(config::GearboxDocument::FromText(text, "<string>"));
  }
  return Wrap(config::GearboxDocument::FromFile(text));
}

py::object Check(const Gearbox& gb) {
  const nlohmann::json doc = RunOnModel(
      gb,
      [](const GearboxSpec& spec, const std::string& source, CallControl& control) {
        // Ctrl-C is seen between the steps (none is polled inside).
        const ComponentModel model = BuildComponentModel(spec);
        ThrowIfCancelled(&control.cancel);
        const ModalSummary modes = FullModelFrequencies(model, app::kReportedModes);
        ThrowIfCancelled(&control.cancel);
        const std::vector<ReducedModel> tiers = app::ReduceAvailableTiers(model);
        nlohmann::json out = app::CheckReport(spec, model, modes, tiers);
        out["file"] = source;
        return out;
      },
      py::none());
  return ToPython(doc);
}

void RegisterInputError(py::module_& m) {
  // gearnvh.InputError(ValueError) with the YAML path, line, value and rule of the loader.
  static py::handle type = py::exception<InputError>(m, "InputError", PyExc_ValueError).release();
  py::setattr(type, "__doc__",
              py::str("Invalid gearbox input. Attributes: path (YAML path such as "
                      "'mesh.backlash'), rule (the rule broken), value (as written), line "
                      "(1-based, 0 when unknown), source (file name, '<string>' or '<dict>')."));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& raised) {
      const InputError e = app::UserNamed(raised, kKeywordInputNames);
      py::object error = type(e.what());
      error.attr("path") = e.path();
      error.attr("rule") = e.rule();
      error.attr("value") = e.value();
      error.attr("line") = e.line();
      error.attr("source") = e.source();
      PyErr_SetObject(type.ptr(), error.ptr());
    }
  });
}

}  // namespace

void BindGearbox(py::module_& m) {
  py::class_<Gearbox>(m, "Gearbox",
                      "A gearbox (schema gearnvh/1): its YAML document and validated model input. "
                      "Create with gearnvh.load().")
      .def("set", &Gearbox::Set, py::arg("path"), py::arg("value"),
           "Set a value by schema path ('operating.torque', 'mesh.backlash', "
           "'operating.excitation[0].amplitude') and revalidate. value: a str as in YAML "
           "('0.3 N*m', '80 um'), a number in SI units, a bool, or a dict/list. Raises "
           "gearnvh.InputError naming the path and rule; the gearbox is unchanged then.")
      .def("get", &Gearbox::Get, py::arg("path"),
           "The value at a schema path as written (a str), or the YAML text of a mapping/list.")
      .def(
          "copy", [](const Gearbox& gb) { return gb; }, "An independent copy.")
      .def("__copy__", [](const Gearbox& gb) { return gb; })
      .def(
          "__deepcopy__", [](const Gearbox& gb, py::dict) { return gb; }, py::arg("memo"))
      .def_property_readonly("name", [](const Gearbox& gb) { return gb.spec().name; })
      .def_property_readonly("source", &Gearbox::source,
                             "The file it came from, '<string>' or '<dict>'.")
      .def_property_readonly(
          "yaml", [](const Gearbox& gb) { return gb.document().Text(); },
          "The YAML document (re-emitted without comments after set()).")
      .def("__repr__", [](const Gearbox& gb) {
        return "<gearnvh.Gearbox '" + gb.spec().name + "' from " + gb.source() +
               (gb.document().Edited() ? ", edited>" : ">");
      });
  m.def("load", &Load, py::arg("source"),
        "Load a gearbox from a YAML file name (str or path), YAML text (anything with a line "
        "break) or a dict with the schema's keys: a Gearbox (schema gearnvh/1, one pair) or a "
        "Train (schema gearnvh/2). Raises gearnvh.InputError on invalid input.");
  m.def("check", &Check, py::arg("gearbox"),
        "Validate and describe a gearbox: the document of `gearnvh check --json` as a dict "
        "(geometry, mesh, fe, tiers; SI units).");
}

}  // namespace gearnvh::python

PYBIND11_MODULE(gearnvh, m) {
  m.doc() =
      "gearnvh: gearbox NVH from Python. load() a gearbox, set() parameters by schema path, run "
      "check, simulate, sweep, atlas, orbits, tiers and (gear trains) validate. Results carry "
      "NumPy views of the C++ "
      "arrays. Ctrl-C interrupts long calls. See docs/python.md.";
  m.attr("__version__") = "0.1.0";
  gearnvh::python::RegisterInputError(m);
  gearnvh::python::BindGearbox(m);
  gearnvh::python::BindTrain(m);
  gearnvh::python::BindSimulate(m);
  gearnvh::python::BindSweepAtlas(m);
  gearnvh::python::BindOrbitsTiers(m);
  gearnvh::python::BindTrainAtlas(m);
  gearnvh::python::BindTrainOrbitsTiers(m);
  gearnvh::python::BindValidation(m);
  gearnvh::python::BindWhine(m);
}
