// The `framequake render` command: argument parsing, display set-up and the
// report printed at the end, so that apps/main.cpp only dispatches to it.
#pragma once

#include <atomic>
#include <functional>
#include <string>

namespace fq::render {

extern const char* const kRenderHelp;

// argv[first] is the first argument after `render`. Returns the exit code:
// 0 done; 2 bad usage or unusable run folder (nothing written); 3 output
// could not be written or no X display could be found or started; 130
// stopped through `stop_requested` (Ctrl-C, SIGTERM or SIGHUP: the unfinished
// animation is removed, PNG frames written so far stay).
// `unknown_option`, when given, words the error for an option kRenderHelp
// does not list (the command line's "did you mean", io/name_hint.h, which
// this module does not depend on); without it: "unknown option 'X'".
int render_command(int argc, char** argv, int first, const std::atomic<bool>* stop_requested = nullptr,
                   const std::function<std::string(const std::string&)>& unknown_option = {});

}  // namespace fq::render
