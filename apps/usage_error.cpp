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

}  // namespace fq_app
