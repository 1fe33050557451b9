// UTF-8 checks and repairs for text that comes from users' files (record
// headers, case files, paths) and goes where UTF-8 is promised: summary.json
// (RFC 8259 section 8.1), the CSV tables, messages. A Latin-1 byte copied
// through unchanged made summary.json unreadable to Python's json (records
// probe: "D\xfczce" in an .AT2 header).
#pragma once

#include <string>
#include <string_view>

namespace fq {

// True when `text` is well-formed UTF-8 (the Unicode Standard, table 3-7:
// no stray continuation bytes, truncated sequences, overlong encodings,
// surrogates or code points above U+10FFFF).
bool is_valid_utf8(std::string_view text);

// `text` with each ill-formed sequence (its maximal subpart, the Unicode
// Standard's recommended practice, section 3.9) replaced by U+FFFD.
std::string utf8_repaired(std::string_view text);

// `text` as it is when it is valid UTF-8; otherwise read as Latin-1 (ISO
// 8859-1: each byte is the code point of its value) and written as UTF-8.
// Header text in older or Windows-written records is Latin-1, and any byte
// string is valid Latin-1, so "D\xfczce" becomes "Düzce".
std::string utf8_from_utf8_or_latin1(std::string_view text);

}  // namespace fq
