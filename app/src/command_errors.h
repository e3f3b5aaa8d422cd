// How commands end. One exit-code table for every command (docs/cli.md):
//   0 ok, 1 invalid input (the message names file:line, the YAML path, the value and the rule),
//   2 usage error (command line), 3 internal error (a bug: an exception we did not expect, or a
//   non-finite number in a result), 4 I/O error (an output that cannot be written or replaced).
#pragma once

#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "input_names.h"

namespace gearnvh::app {

enum ExitCode : int { kExitOk = 0, kExitInput = 1, kExitUsage = 2, kExitInternal = 3, kExitIo = 4 };

// An output that cannot be written, replaced or locked (exit 4). The message names the path;
// `reason` is the system's alone ("No space left on device"), empty when there is none.
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& message, std::string reason = {})
      : std::runtime_error(message), reason_(std::move(reason)) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// A result that is not a finite number (exit 3): a bug or an unguarded corner of the model, never
// something to print.
class NonFiniteResult : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// The message of an input error, at the YAML path the user wrote (UserNamed), naming `file` when
// the error was raised below the loader (range rules of the model, solver options) and so carries
// no source, with the line and the value as
// written of its YAML path in that file when `where` holds the file's locations (the
// LoadedGearbox::locations of its load; empty when the file was not loaded).
inline std::string InputErrorMessage(const InputError& e, const std::string& file,
                                     const config::SourceLocations& where = {}) {
  return config::LocatedIn(UserNamed(e), where, file).what();
}

// An input error about a command-line option ("--resume needs --out") is a usage error.
inline int ExitCodeOf(const InputError& e) {
  return e.path().rfind("--", 0) == 0 ? kExitUsage : kExitInput;
}

// Runs `body` (returning the exit code) and maps what it throws onto the exit-code table. Anything
// not listed here reaches main(), which reports an internal error (3). The body stores the loaded
// file's locations in its config::SourceLocations& argument (`where = loaded.locations`), so input
// errors raised after loading name their line.
template <typename Body>
int RunReportingErrors(const std::string& file, Body&& body) {
  config::SourceLocations where;
  try {
    return body(where);
  } catch (const InputError& e) {
    std::cerr << "error: " << InputErrorMessage(e, file, where) << "\n";
    return ExitCodeOf(e);
  } catch (const IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  } catch (const NonFiniteResult& e) {
    std::cerr << "internal error: " << file << ": " << e.what() << "\n";
    return kExitInternal;
  } catch (const std::runtime_error& e) {
    // Failures the library reports as runtime_error (a run that could not be completed).
    std::cerr << "error: " << e.what() << "\n";
    return kExitInput;
  }
}

}  // namespace gearnvh::app
