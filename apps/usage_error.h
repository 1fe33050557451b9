// Mistakes on the command line (an unknown option, a missing value): one
// message, the command's usage text, exit code 2. Shared by every command.
#pragma once

#include <string>

namespace fq_app {

// Prints "framequake: error: MESSAGE", then `usage`, and exits with 2 (bad input).
[[noreturn]] void usage_error(const std::string& message, const char* usage);

// usage_error for an option `usage` does not list, naming the one it lists
// that was probably meant (io/name_hint.h, nearest_option).
[[noreturn]] void unknown_option(const std::string& option, const char* usage);

}  // namespace fq_app
