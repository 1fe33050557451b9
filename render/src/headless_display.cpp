#include "render/headless_display.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <X11/Xlib.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>

namespace fq::render {

namespace {

bool find_on_path(const char* program, std::string& out_path) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / program;
    if (access(candidate.c_str(), X_OK) == 0) {
      out_path = candidate.string();
      return true;
    }
  }
  return false;
}

constexpr const char* kHowTo =
    "install the Debian package xvfb (apt-get install xvfb), or run the command under "
    "`xvfb-run -a`, or set DISPLAY to an X display";

}  // namespace

HeadlessDisplay::~HeadlessDisplay() {
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

bool HeadlessDisplay::ensure(std::string& out_error) {
  const char* display = std::getenv("DISPLAY");
  if (display && *display) {
    // VTK aborts the process on a display it cannot open: check first.
    if (Display* d = XOpenDisplay(nullptr)) {
      XCloseDisplay(d);
      return true;
    }
    std::fprintf(stderr, "framequake render: cannot open X display '%s' (DISPLAY); starting a private Xvfb instead\n",
                 display);
  }
  std::string xvfb;
  if (!find_on_path("Xvfb", xvfb)) {
    out_error = std::string("no X display (DISPLAY is unset) and Xvfb is not on PATH: ") + kHowTo;
    return false;
  }
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    out_error = std::string("cannot create a pipe for Xvfb: ") + std::strerror(errno);
    return false;
  }
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    out_error = std::string("cannot start Xvfb: ") + std::strerror(errno);
    close(fds[0]);
    close(fds[1]);
    return false;
  }
  if (pid == 0) {
    // Child: the server must not outlive us, and must not write on our terminal.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    // Its own process group: a Ctrl-C (or `timeout`'s signal) goes to the
    // terminal's whole foreground group, and would end the server before
    // the render stops cleanly and removes its unfinished animation (X
    // connection broken, .part left). It still ends with us (PDEATHSIG).
    setpgid(0, 0);
    const int devnull = open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      dup2(devnull, 0);
      dup2(devnull, 1);
      dup2(devnull, 2);
    }
    const int keep = dup(fds[1]);  // without O_CLOEXEC, survives exec
    const std::string fd_text = std::to_string(keep);
    execl(xvfb.c_str(), "Xvfb", "-displayfd", fd_text.c_str(), "-screen", "0", "2560x1440x24", "-nolisten", "tcp",
          "-noreset", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  pid_ = pid;
  // The server writes its display number followed by a newline when ready.
  std::string number;
  pollfd p{fds[0], POLLIN, 0};
  constexpr int kTimeoutMs = 20000;
  bool ok = false;
  while (true) {
    const int r = poll(&p, 1, kTimeoutMs);
    if (r <= 0) break;  // timeout or error
    char c = 0;
    const ssize_t n = read(fds[0], &c, 1);
    if (n <= 0) break;  // server exited
    if (c == '\n') {
      ok = !number.empty();
      break;
    }
    number.push_back(c);
  }
  close(fds[0]);
  if (!ok) {
    out_error = "Xvfb (" + xvfb + ") did not report a display within 20 s; " + kHowTo;
    return false;
  }
  setenv("DISPLAY", (":" + number).c_str(), 1);
  return true;
}

}  // namespace fq::render
