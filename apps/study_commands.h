// Commands that run several cases: `compare` (cases side by side) and
// `sweep` (cases over amplitude scales and records).
#pragma once

#include <atomic>

namespace fq_app {

int command_compare(int argc, char** argv, const std::atomic<bool>* stop_requested);
int command_sweep(int argc, char** argv, const std::atomic<bool>* stop_requested);

// Their usage texts (for errors found before the command parses its options).
const char* compare_help();
const char* sweep_help();

}  // namespace fq_app
