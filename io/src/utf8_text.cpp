#include "io/utf8_text.h"

#include <cstddef>

namespace fq {

namespace {

struct Sequence {
  std::size_t length;  // bytes of the sequence, or of its maximal ill-formed subpart (>= 1)
  bool ok;
};

// The sequence starting at text[i], per the Unicode Standard's table 3-7 of
// well-formed UTF-8 byte sequences: the lead byte sets the length and the
// range of the second byte (which excludes overlong forms, surrogates and
// code points above U+10FFFF); later bytes are 80..BF.
Sequence next_sequence(std::string_view text, std::size_t i) {
  const auto b0 = static_cast<unsigned char>(text[i]);
  if (b0 < 0x80) return {1, true};
  std::size_t trailing = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    trailing = 1;
  } else if (b0 == 0xE0) {
    trailing = 2;
    lo = 0xA0;
  } else if ((b0 >= 0xE1 && b0 <= 0xEC) || b0 == 0xEE || b0 == 0xEF) {
    trailing = 2;
  } else if (b0 == 0xED) {
    trailing = 2;
    hi = 0x9F;
  } else if (b0 == 0xF0) {
    trailing = 3;
    lo = 0x90;
  } else if (b0 >= 0xF1 && b0 <= 0xF3) {
    trailing = 3;
  } else if (b0 == 0xF4) {
    trailing = 3;
    hi = 0x8F;
  } else {
    return {1, false};  // a continuation byte, C0, C1 or F5..FF: never a lead byte
  }
  for (std::size_t k = 1; k <= trailing; ++k) {
    if (i + k >= text.size()) return {k, false};
    const auto b = static_cast<unsigned char>(text[i + k]);
    if (b < lo || b > hi) return {k, false};
    lo = 0x80;
    hi = 0xBF;
  }
  return {trailing + 1, true};
}

}  // namespace

bool is_valid_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const Sequence s = next_sequence(text, i);
    if (!s.ok) return false;
    i += s.length;
  }
  return true;
}

std::string utf8_repaired(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const Sequence s = next_sequence(text, i);
    if (s.ok)
      out.append(text.substr(i, s.length));
    else
      out.append("\xEF\xBF\xBD");  // U+FFFD REPLACEMENT CHARACTER
    i += s.length;
  }
  return out;
}

std::string utf8_from_utf8_or_latin1(std::string_view text) {
  if (is_valid_utf8(text)) return std::string(text);
  std::string out;
  out.reserve(text.size() * 2);
  for (const char c : text) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x80) {
      out.push_back(c);
    } else {  // U+0080..U+00FF in two bytes: 110000xx 10xxxxxx
      out.push_back(static_cast<char>(0xC0 | (b >> 6)));
      out.push_back(static_cast<char>(0x80 | (b & 0x3F)));
    }
  }
  return out;
}

}  // namespace fq
