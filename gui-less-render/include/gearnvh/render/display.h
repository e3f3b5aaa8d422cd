// An X display for VTK's offscreen rendering (docs/design.md §7).
//
// Debian's VTK 9.1 renders through GLX only (no OSMesa/EGL build): without an X server a render
// would crash. EnsureDisplay() makes sure one is usable before anything is drawn:
//   DISPLAY set      -> XOpenDisplay must succeed, else kDisplayUnusable (names $DISPLAY);
//   DISPLAY unset    -> start a private `Xvfb -displayfd` (it picks a free display number and
//                       reports it when ready; 10 s limit), set DISPLAY for this process, and
//                       stop the server at exit; kXvfbMissing when no Xvfb is on PATH,
//                       kXvfbFailed when it does not come up.
// Thread-safe; the outcome of the first call is kept for the process.
#pragma once

#include <string>

namespace gearnvh::render {

struct DisplayStatus {
  enum class Info { kSuccess, kDisplayUnusable, kXvfbMissing, kXvfbFailed };
  Info info = Info::kSuccess;
  std::string message;  // what to do about it, for the user
  std::string display;  // the DISPLAY in use
  bool own_xvfb = false;
  bool ok() const { return info == Info::kSuccess; }
};

const DisplayStatus& EnsureDisplay();

}  // namespace gearnvh::render
