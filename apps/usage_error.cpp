#include "usage_error.h"

#include <cstdlib>
#include <iostream>

#include "io/name_hint.h"

namespace fq_app {

void usage_error(const std::string& message, const char* usage) {
  std::cerr << "framequake: error: " << message << "\n\n" << usage;
  std::exit(2);
}

void unknown_option(const std::string& option, const char* usage) {
  usage_error(fq::unknown_option_message(option, usage), usage);
}

bool looks_like_option(const std::string& word) {
  if (word.size() < 3 || word.compare(0, 2, "--") != 0) return false;
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  if (!letter(word[2])) return false;
  for (std::size_t k = 3; k < word.size(); ++k)
    if (!letter(word[k]) && !(word[k] >= '0' && word[k] <= '9') && word[k] != '-') return false;
  return true;
}

std::string option_value(const char* name, int argc, char** argv, int i, const char* usage) {
  if (i + 1 >= argc) usage_error(std::string(name) + " needs a value", usage);
  const std::string value = argv[i + 1];
  if (value.empty()) usage_error(std::string(name) + " needs a value, got an empty one", usage);
  if (looks_like_option(value))
    usage_error(std::string(name) + " needs a value, got the option '" + value + "' (a file or folder whose name "
                    "starts with '--' is written ./" + value + ")",
                usage);
  return value;
}

}  // namespace fq_app
