// A text field of a CSV file, quoted per RFC 4180 where it must be: names
// and modes are identifiers, but a comma, quote or line end in one must not
// shift the columns (events.csv, the study tables).
#pragma once

#include <string>
#include <string_view>

namespace fq {

// `text` as it is, or in double quotes with each quote doubled when it holds
// a comma, a quote or a line end; ill-formed UTF-8 becomes U+FFFD
// (io/utf8_text.h).
std::string csv_text(std::string_view text);

}  // namespace fq
