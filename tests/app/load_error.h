// Helpers of the loader-message tests: an example file's text, a text edit, and the message
// loading a text gives.
#pragma once

#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::testing {

// The text of examples/`name`.
inline std::string Example(const std::string& name) {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/" + name);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `text` with the first `from` replaced by `to` (which must occur).
inline std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// The message of the InputError loading `text` as "t.yaml" throws ("" when it loads).
inline std::string LoadError(const std::string& text) {
  try {
    (void)config::LoadAnyGearboxFromString(text, "t.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace gearnvh::testing
