// An X display for VTK's offscreen rendering when none is attached.
//
// Debian 12's VTK 9.1 renders through GLX only (no EGL or OSMesa build), so
// even offscreen rendering needs an X server. When DISPLAY is unset,
// HeadlessDisplay starts a private Xvfb (package `xvfb`) with -displayfd: the
// server picks a free display number itself and reports it when ready, so
// parallel renders (ctest -j) never race for a number as `xvfb-run -a` can.
// The server is stopped by the destructor, and dies with this process
// (PR_SET_PDEATHSIG) if it crashes.
#pragma once

#include <string>
#include <sys/types.h>

namespace fq::render {

class HeadlessDisplay {
 public:
  HeadlessDisplay() = default;
  ~HeadlessDisplay();
  HeadlessDisplay(const HeadlessDisplay&) = delete;
  HeadlessDisplay& operator=(const HeadlessDisplay&) = delete;

  // Makes sure DISPLAY names a display: keeps an existing one that opens,
  // else (unset, or it does not open) starts Xvfb and sets DISPLAY. Returns false with a message saying what to install
  // or run when neither works.
  bool ensure(std::string& out_error);
  bool started_server() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

}  // namespace fq::render
