// How commands report bad input: "error: file:line: yaml.path: rule, got 'value'" on stderr and
// exit code 1 (main() maps anything else to 3, internal error).
#pragma once

#include <iostream>
#include <stdexcept>
#include <string>

#include "gearnvh/model/input_error.h"

namespace gearnvh::app {

// The message of an input error, naming `file` when the error was raised below the loader (range
// rules of the model, solver options) and so carries no source.
inline std::string InputErrorMessage(const InputError& e, const std::string& file) {
  return e.source().empty() ? e.WithSource(file).what() : e.what();
}

// Runs `body` (returning the exit code). Input errors and outputs that cannot be written
// (permissions, disk full, a file in the way: std::runtime_error from the atomic writer, which
// leaves no partial file) become a clear message and exit 1.
template <typename Body>
int RunReportingErrors(const std::string& file, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << "error: " << InputErrorMessage(e, file) << "\n";
    return 1;
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace gearnvh::app
