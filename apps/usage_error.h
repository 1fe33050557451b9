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

// True for a word written as an option name: "--" then a letter, then
// letters, digits and hyphens ("--no-figure"). An option that takes a value
// and is followed by such a word was given none: "--out --no-figure" wrote
// a study into a folder named "--no-figure" (studies probe).
bool looks_like_option(const std::string& word);

// The value after option `name` at argv[i + 1]: refused (usage_error) when
// there is none, when it is empty, or when it looks like an option; a
// folder or file whose name starts with "--" is given as ./--name.
std::string option_value(const char* name, int argc, char** argv, int i, const char* usage);

}  // namespace fq_app
