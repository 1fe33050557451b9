#include "io/csv_text.h"

#include "io/utf8_text.h"

namespace fq {

std::string csv_text(std::string_view raw) {
  // The tables are UTF-8, as spreadsheet and pandas readers take them by
  // default; a path or record name with a byte that is not UTF-8 would make
  // the whole file unreadable to them.
  const bool valid = is_valid_utf8(raw);
  const std::string repaired = valid ? std::string() : utf8_repaired(raw);
  const std::string_view text = valid ? raw : std::string_view(repaired);
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted.push_back('"');
    quoted.push_back(c);
  }
  quoted.push_back('"');
  return quoted;
}

}  // namespace fq
