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
  const auto hint = fq::nearest_option(option, usage);
  usage_error("unknown option '" + option + "'" + (hint ? " (did you mean '" + *hint + "'?)" : ""), usage);
}

}  // namespace fq_app
