// gearnvh.Gearbox (schema gearnvh/1) and gearnvh.Train (schema gearnvh/2): a YAML document and
// its validated spec. Edits go through the loader (config::GearboxDocument), so every schema rule
// applies.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "config/gearbox_document.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"
#include "input_names.h"

namespace gearnvh::python {

namespace py = pybind11;

// gb.set's edit: `value` is a str as written ("0.3 N*m"), an int/float as SI, a bool, or a
// dict/list; the document is edited and reloaded (either schema; it cannot change).
// `path` is a str (else TypeError); a str path or value UTF-8 cannot encode is an InputError.
config::LoadedGearbox SetByPath(config::GearboxDocument& document, const py::object& path,
                                const py::object& value);

// A schema-1 gearbox (one pair).
class Gearbox {
 public:
  Gearbox(config::GearboxDocument document, GearboxSpec spec)
      : document_(std::move(document)), spec_(std::move(spec)) {}

  void Set(const py::object& path, const py::object& value) {
    spec_ = *SetByPath(document_, path, value).pair;
  }
  std::string Get(const std::string& path) const { return document_.Get(path); }

  const GearboxSpec& spec() const { return spec_; }
  const config::GearboxDocument& document() const { return document_; }
  // The name results carry as `file` (what the command line prints for the file it was given).
  const std::string& source() const { return document_.Source(); }

 private:
  config::GearboxDocument document_;
  GearboxSpec spec_;
};

// A schema-2 gear train.
class Train {
 public:
  Train(config::GearboxDocument document, TrainSpec spec)
      : document_(std::move(document)), spec_(std::move(spec)) {}

  void Set(const py::object& path, const py::object& value) {
    spec_ = SetByPath(document_, path, value).train;
  }
  std::string Get(const std::string& path) const { return document_.Get(path); }

  const TrainSpec& spec() const { return spec_; }
  const config::GearboxDocument& document() const { return document_; }
  const std::string& source() const { return document_.Source(); }

 private:
  config::GearboxDocument document_;
  TrainSpec spec_;
};

// The library's names for the keywords of the module's functions (tier=, cycles=, transient=);
// the other inputs the library checks keep their YAML paths (app/src/input_names.h).
inline const app::InputNames kKeywordInputNames{
    .tier = "tier", .cycles = "cycles", .transient = "transient"};

// Runs `body`; an InputError raised below the loader (range rules of the model, solver options)
// carries no source and is given the gearbox's, as the command line does, at the name the user
// wrote (UserNamed: the copy with the source is a plain InputError).
template <typename Body>
auto NamingSource(const std::string& source, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const InputError& e) {
    if (!e.source().empty()) throw;
    throw app::UserNamed(e, kKeywordInputNames).WithSource(source);
  }
}

void BindGearbox(py::module_& m);
void BindSimulate(py::module_& m);
void BindSweepAtlas(py::module_& m);
void BindOrbitsTiers(py::module_& m);
void BindTrain(py::module_& m);
void BindTrainAtlas(py::module_& m);
void BindTrainOrbitsTiers(py::module_& m);
void BindValidation(py::module_& m);
void BindWhine(py::module_& m);

}  // namespace gearnvh::python
