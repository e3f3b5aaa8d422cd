#include "gearnvh/render/display.h"

#include <X11/Xlib.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <vector>

extern char** environ;

namespace gearnvh::render {

namespace {

pid_t g_xvfb = -1;

void StopXvfb() {
  if (g_xvfb > 0) {
    ::kill(g_xvfb, SIGTERM);
    int status = 0;
    ::waitpid(g_xvfb, &status, 0);
    g_xvfb = -1;
  }
}

bool CanOpen(const char* name) {
  Display* d = XOpenDisplay(name);
  if (d == nullptr) return false;
  XCloseDisplay(d);
  return true;
}

std::string FindOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

// Why an Xvfb that closed its -displayfd pipe is gone: its exit status or signal (reaped here, so
// StopXvfb has nothing left to do), and how to see its own message, which gearnvh discards.
std::string XvfbEndedMessage(const std::string& xvfb) {
  int status = 0;
  pid_t reaped = 0;
  for (int i = 0; i < 20 && reaped == 0; ++i) {  // it is exiting: wait up to 1 s for the status
    reaped = ::waitpid(g_xvfb, &status, WNOHANG);
    if (reaped == 0) ::usleep(50000);
  }
  std::string how = "closed its display pipe";
  if (reaped == g_xvfb) {
    g_xvfb = -1;
    if (WIFEXITED(status)) how = "exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) how = "was killed by signal " + std::to_string(WTERMSIG(status));
  }
  return "Xvfb (" + xvfb + ") " + how + " before it was ready (run `" + xvfb +
         " -displayfd 1` to see why), or set DISPLAY to a running X server";
}

// Held while an Xvfb starts, so two gearnvh processes (MPI ranks, parallel runs) sharing a
// temporary directory never start theirs at the same moment: two Xvfbs scanning for a free display
// together can both name the same one, and the loser exits after its client connected (XIO error).
// Released on close. The wait is bounded: a holder stopped mid-start (SIGSTOP, a debugger) costs at
// most kXvfbStartLockWait, after which this start goes ahead unserialised, as without the file.
constexpr auto kXvfbStartLockWait = std::chrono::seconds(15);  // > the 10 s start deadline

class XvfbStartLock {
 public:
  XvfbStartLock() {
    std::error_code error;
    const std::filesystem::path dir = std::filesystem::temp_directory_path(error);  // $TMPDIR
    const std::string path =
        ((error ? std::filesystem::path("/tmp") : dir) / ".gearnvh-xvfb-start.lock").string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0) fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) return;  // without the file: start unserialised
    const auto deadline = std::chrono::steady_clock::now() + kXvfbStartLockWait;
    while (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      // Another error (ENOLCK on a file system without locks): start unserialised at once.
      if (errno != EWOULDBLOCK && errno != EINTR) return;
      if (std::chrono::steady_clock::now() >= deadline) return;
      ::usleep(20000);
    }
  }
  ~XvfbStartLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  XvfbStartLock(const XvfbStartLock&) = delete;
  XvfbStartLock& operator=(const XvfbStartLock&) = delete;

 private:
  int fd_ = -1;
};

DisplayStatus StartXvfb() {
  DisplayStatus s;
  const XvfbStartLock serialised;
  const std::string xvfb = FindOnPath("Xvfb");
  if (xvfb.empty()) {
    s.info = DisplayStatus::Info::kXvfbMissing;
    s.message =
        "images need an X display: DISPLAY is not set and Xvfb is not installed (Debian: "
        "apt-get install xvfb xauth libgl1-mesa-dri), or set DISPLAY to a running X server";
    return s;
  }
  int fds[2];
  if (::pipe(fds) != 0) {
    s.info = DisplayStatus::Info::kXvfbFailed;
    s.message = "could not start Xvfb: pipe() failed";
    return s;
  }
  const std::string fd = std::to_string(fds[1]);
  std::vector<std::string> args{xvfb,           "-displayfd", fd,    "-screen", "0",
                                "1920x1200x24", "-nolisten",  "tcp", "-noreset"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // fork + exec rather than posix_spawn: the child must ask the kernel to kill it when gearnvh
  // dies (PR_SET_PDEATHSIG), so a killed gearnvh never leaves an Xvfb behind. Between fork and
  // exec only async-signal-safe calls.
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);  // gearnvh blocks SIGTERM for its cleanup thread
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(127);
    ::close(fds[0]);
    // Xvfb's own chatter (font warnings) is not for the user of gearnvh.
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
    }
    ::execve(xvfb.c_str(), argv.data(), environ);
    ::_exit(127);
  }
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    s.info = DisplayStatus::Info::kXvfbFailed;
    s.message = "could not start " + xvfb;
    return s;
  }
  g_xvfb = pid;
  std::atexit(StopXvfb);
  // Xvfb writes the display number and a newline once it accepts connections.
  std::string number;
  bool closed = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    char c = 0;
    if (::read(fds[0], &c, 1) != 1) {
      closed = true;  // Xvfb died (or closed the descriptor) before naming its display
      break;
    }
    if (c == '\n') break;
    number += c;
  }
  ::close(fds[0]);
  if (number.empty()) {
    s.info = DisplayStatus::Info::kXvfbFailed;
    s.message = closed ? XvfbEndedMessage(xvfb) : "Xvfb (" + xvfb + ") did not start within 10 s";
    StopXvfb();
    return s;
  }
  s.display = ":" + number;
  ::setenv("DISPLAY", s.display.c_str(), 1);
  s.own_xvfb = true;
  if (!CanOpen(s.display.c_str())) {
    StopXvfb();
    s.info = DisplayStatus::Info::kXvfbFailed;
    s.message = "Xvfb started on " + s.display + " but the display cannot be opened";
  }
  return s;
}

}  // namespace

const DisplayStatus& EnsureDisplay() {
  static DisplayStatus status;
  static std::once_flag once;
  std::call_once(once, [] {
    const char* display = std::getenv("DISPLAY");
    if (display != nullptr && *display != '\0') {
      status.display = display;
      if (!CanOpen(display)) {
        status.info = DisplayStatus::Info::kDisplayUnusable;
        status.message = std::string("cannot open the X display DISPLAY=") + display +
                         " for rendering images; unset DISPLAY to let gearnvh start its own Xvfb";
      }
      return;
    }
    status = StartXvfb();
  });
  return status;
}

}  // namespace gearnvh::render
