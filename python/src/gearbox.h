// gearnvh.Gearbox: a YAML gearbox document and its validated spec. Edits go through the loader
// (config::GearboxDocument), so every schema rule applies.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "config/gearbox_document.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::python {

namespace py = pybind11;

class Gearbox {
 public:
  explicit Gearbox(config::GearboxDocument document)
      : document_(std::move(document)), spec_(document_.Load()) {}

  // gb.set(path, value): str as written ("0.3 N*m"), int/float as SI, bool, dict/list.
  void Set(const std::string& path, const py::object& value);
  std::string Get(const std::string& path) const { return document_.Get(path); }

  const GearboxSpec& spec() const { return spec_; }
  const config::GearboxDocument& document() const { return document_; }
  // The name results carry as `file` (what the command line prints for the file it was given).
  const std::string& source() const { return document_.Source(); }

 private:
  config::GearboxDocument document_;
  GearboxSpec spec_;
};

// Runs `body`; an InputError raised below the loader (range rules of the model, solver options)
// carries no source and is given the gearbox's, as the command line does.
template <typename Body>
auto NamingSource(const std::string& source, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const InputError& e) {
    if (!e.source().empty()) throw;
    throw e.WithSource(source);
  }
}

void BindGearbox(py::module_& m);
void BindSimulate(py::module_& m);
void BindSweepAtlas(py::module_& m);
void BindOrbitsTiers(py::module_& m);

}  // namespace gearnvh::python
