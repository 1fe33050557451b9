// Commands that run several cases: `compare` (cases side by side) and
// `sweep` (cases over amplitude scales and records).
#pragma once

#include <atomic>

namespace fq_app {

int command_compare(int argc, char** argv, const std::atomic<bool>* stop_requested);
int command_sweep(int argc, char** argv, const std::atomic<bool>* stop_requested);

}  // namespace fq_app
