// A gearbox YAML document (schema gearnvh/1 or gearnvh/2) that can be edited by schema path before
// it is loaded (the Python API's gb.set). Every edit goes through the normal loader
// (LoadAnyGearboxFromString), so every rule of the schema applies and errors name the YAML path,
// the value and the rule. An edit cannot change the document's schema.
#pragma once

#include <string>

#include "config/gearbox_loader.h"

namespace gearnvh::config {

class GearboxDocument {
 public:
  // YAML text as written; throws InputError ("not valid YAML") naming `source` and the line.
  static GearboxDocument FromText(const std::string& text, const std::string& source = "<string>");
  // A file (at most 16 MiB, as LoadGearboxFile); `source` is the path.
  static GearboxDocument FromFile(const std::string& path);
  // Flow YAML or JSON (a Python dict dumped as JSON), re-emitted in block style so that error
  // lines point into Text().
  static GearboxDocument FromData(const std::string& flow_text, const std::string& source);

  // The validated SI spec of either schema, through LoadAnyGearboxFromString.
  LoadedGearbox Load() const;

  // Sets the node at a schema path ("operating.torque", "operating.excitation[0].amplitude" or
  // "operating.excitation.0.amplitude") and reloads: SetScalar to a scalar as written ("0.3 N*m",
  // "2.5e-4": SI), SetYaml to a YAML (or JSON) value such as a mapping or a list. Missing mapping
  // keys are created. Returns the new spec; throws InputError naming the path (or the rule the
  // edited gearbox breaks, or `schema` when the edit would change it) and leaves the document
  // unchanged on any error.
  LoadedGearbox SetScalar(const std::string& path, const std::string& value);
  LoadedGearbox SetYaml(const std::string& path, const std::string& yaml);

  // The node at `path` as YAML text (a scalar as written); throws InputError when it is absent.
  std::string Get(const std::string& path) const;

  const std::string& Text() const { return text_; }
  const std::string& Source() const { return source_; }
  // After an edit the text is re-emitted (comments are lost) and error lines refer to Text():
  // messages name the source as "SOURCE (edited)".
  bool Edited() const { return edited_; }

 private:
  GearboxDocument(std::string text, std::string source, bool edited)
      : text_(std::move(text)), source_(std::move(source)), edited_(edited) {}
  std::string LoadSource() const { return edited_ ? source_ + " (edited)" : source_; }
  template <typename Assign>
  LoadedGearbox Edit(const std::string& path, const Assign& assign);

  std::string text_;
  std::string source_;
  bool edited_ = false;
};

}  // namespace gearnvh::config
