#include "io/accelerogram.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>
#include <vector>

#include "dem_core/types.h"
#include "io/input_error.h"
#include "io/utf8_text.h"

namespace fq {

namespace {

// Bounds on what a ground-motion record can hold; outside them a file is
// refused at the line that breaks them, because only a wrong unit or a
// typing error gets there (a probe's value of 1e300 g ran to the end with
// infinite displacements and a balance error of 1e290).
// - Acceleration: the largest ground acceleration ever recorded is about
//   4 g (4 022 cm/s^2, three components combined, station IWTH25 in the
//   2008 Iwate-Miyagi Nairiku earthquake; Aoi et al., Science 322, 2008).
//   20 g is five times that; a record in cm/s^2 read as g gives hundreds.
// - Sampling interval: strong-motion records are sampled at 50-1000 Hz
//   (dt 0.001-0.02 s). Above 1 s the record cannot carry motion above
//   0.5 Hz, where a building's response lies; below 1e-6 s (1 MHz) no
//   accelerometer samples, and a time in ms read as s gives that.
constexpr double kMinSampleInterval_s = 1e-6;
constexpr double kMaxSampleInterval_s = 1.0;

std::string sample_interval_problem(double dt_s) {
  if (dt_s >= kMinSampleInterval_s && dt_s <= kMaxSampleInterval_s) return "";
  std::ostringstream why;
  why << "expected a sampling interval of " << kMinSampleInterval_s << " to " << kMaxSampleInterval_s
      << " s (strong-motion records are sampled every 0.001-0.02 s), got " << dt_s << " s: a time unit off?";
  return why.str();
}

// `value` as written, in a unit of `unit_mps2` m/s^2. Compared in g, so that
// a huge value written in g (1e308) is quoted as itself, not as the inf its
// conversion to m/s^2 overflows to (probe).
std::string acceleration_problem(double value, double unit_mps2) {
  const double value_g = value * (unit_mps2 / kStandardGravity_mps2);
  if (std::abs(value_g) <= kMaxAbsAcceleration_g) return "";
  std::ostringstream why;
  why << std::setprecision(4) << "expected at most " << kMaxAbsAcceleration_g
      << " g in magnitude (the largest ground acceleration ever recorded is about 4 g), got " << value_g
      << " g: a wrong unit (cm/s^2 read as g?) or a typing error";
  return why.str();
}

// ---- text access -------------------------------------------------------------

// Whole file in memory: records are at most a few MB, and one read followed
// by a pointer walk is far faster than line-wise stream extraction.
std::string load_file(const std::filesystem::path& file, const char* expected_content) {
  const std::string name = file.string();
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(status))
    throw InputError(name, 0, "file", std::string("file not found; expected ") + expected_content);
  if (std::filesystem::is_directory(status))
    throw InputError(name, 0, "file", std::string("is a directory; expected ") + expected_content);
  // A pipe would block the open until a writer came (Ctrl-C cannot stop
  // that; a CLI probe's sweep --record on a FIFO hung), a device never ends.
  if (!std::filesystem::is_regular_file(status))
    throw InputError(name, 0, "file",
                     std::string("is not a regular file (a pipe, device or socket); expected ") + expected_content);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name, 0, "file", std::string("cannot open for reading; expected ") + expected_content);
  std::string text;
  char chunk[1 << 16];
  while (in) {
    in.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(name, 0, "file", std::string("read error; expected ") + expected_content);
  // A DOS end-of-file mark (Ctrl-Z, 0x1A) as the last byte(s), which old
  // DOS-written files carry, is not content. Anywhere else 0x1A is refused
  // as a non-text byte (require_text): inside a file it means binary data.
  while (!text.empty() && text.back() == '\x1A') text.pop_back();
  if (text.empty()) throw InputError(name, 0, "file", std::string("the file is empty; expected ") + expected_content);
  // A UTF-8 byte-order mark, as some Windows editors write, is not content.
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  return text;
}

// Yields lines without their terminator; LF, CRLF and lone CR all end a line.
// A terminator at the very end does not start an extra empty line.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t begin = pos_;
    std::size_t end = begin;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    line = text_.substr(begin, end - begin);
    pos_ = end;
    if (pos_ < text_.size()) {
      if (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ++pos_;
      ++pos_;
    }
    ++line_no_;
    return true;
  }
  int line_no() const { return line_no_; }  // 1-based number of the last line returned

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_no_ = 0;
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

// The words of `line` between blanks and any of `separators` (none empty).
std::vector<std::string_view> split_words(std::string_view line, std::string_view separators) {
  const auto separates = [&](char c) { return is_blank(c) || separators.find(c) != std::string_view::npos; };
  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && separates(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !separates(line[j])) ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}
bool is_alpha(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char to_upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

// Control bytes other than blanks mean the file is not text (a binary file,
// a compressed download, a wrong file picked). Bytes >= 0x80 are allowed:
// UTF-8 station names and comments are text.
void require_text(const std::string& file, int line_no, std::string_view line, const char* field) {
  for (const char c : line) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && !is_blank(c)) || u == 0x7F) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned>(u));
      throw InputError(file, line_no, field,
                       std::string("expected text, found the non-text byte ") + hex + " (is this a binary file?)");
    }
  }
}

// Position of `word` in `s` at or after `from`, ignoring case; npos if absent.
std::size_t find_ci(std::string_view s, std::string_view word, std::size_t from = 0) {
  if (word.size() > s.size()) return std::string_view::npos;
  for (std::size_t i = from; i + word.size() <= s.size(); ++i) {
    std::size_t k = 0;
    while (k < word.size() && to_upper(s[i + k]) == to_upper(word[k])) ++k;
    if (k == word.size()) return i;
  }
  return std::string_view::npos;
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMaxShown = 60;  // keep messages one line long
  // The file's text as UTF-8 (a Latin-1 header reached the terminal as raw
  // bytes), cut at a character boundary, not inside a multi-byte one.
  const std::string text = utf8_from_utf8_or_latin1(s);
  std::size_t shown = std::min(text.size(), kMaxShown);
  while (shown > 0 && shown < text.size() && (static_cast<unsigned char>(text[shown]) & 0xC0) == 0x80) --shown;
  std::string out = "'";
  out.append(text, 0, shown);
  if (shown < text.size()) out += "...";
  out += "'";
  return out;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// ---- numbers -----------------------------------------------------------------

enum class NumberStatus { Ok, NotANumber, OutOfRange, TooSmall };

// Whether a number from_chars found out of range is too small rather than
// too large: its decimal order of magnitude (the exponent, plus the digits
// before the point or less the zeros after it) is negative. "1e-400" rounds
// to 0 and was refused as "not finite", which names the wrong problem.
bool order_of_magnitude_negative(std::string_view tok) {
  if (!tok.empty() && (tok.front() == '-' || tok.front() == '+')) tok.remove_prefix(1);
  const std::size_t e_pos = tok.find_first_of("eE");
  const std::string_view mantissa = tok.substr(0, e_pos);
  long long exponent = 0;
  if (e_pos != std::string_view::npos) {
    std::string_view e = tok.substr(e_pos + 1);
    const bool negative = !e.empty() && e.front() == '-';
    if (!e.empty() && (e.front() == '+' || e.front() == '-')) e.remove_prefix(1);
    // An exponent of 20 digits or more decides alone.
    if (std::from_chars(e.data(), e.data() + e.size(), exponent).ec == std::errc::result_out_of_range) return negative;
    if (negative) exponent = -exponent;
  }
  const std::size_t dot = std::min(mantissa.find('.'), mantissa.size());
  const std::size_t first = mantissa.find_first_of("123456789");
  if (first == std::string_view::npos) return false;  // zero is in range
  const long long order = first < dot ? static_cast<long long>(dot - first - 1)
                                      : -static_cast<long long>(first - dot);
  return exponent + order < 0;
}

// Whole token as a double: from_chars' syntax plus a leading '+' and Fortran
// 'D' exponents. ".5" and "-.1416764E-03" are valid (Fortran E-format drops
// the leading zero). nan/inf parse and are caught by the caller's finiteness
// check, so the message can say "not finite" rather than "not a number".
NumberStatus parse_number(std::string_view tok, double& out) {
  if (tok.empty()) return NumberStatus::NotANumber;
  if (tok.front() == '+') {
    tok.remove_prefix(1);
    if (tok.empty() || tok.front() == '+' || tok.front() == '-') return NumberStatus::NotANumber;
  }
  char buf[64];
  const std::size_t d_pos = tok.find_first_of("dD");
  if (d_pos != std::string_view::npos) {
    if (tok.size() >= sizeof buf) return NumberStatus::NotANumber;
    std::copy(tok.begin(), tok.end(), buf);
    buf[d_pos] = 'E';
    tok = std::string_view(buf, tok.size());
  }
  const char* const end = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(tok.data(), end, out, std::chars_format::general);
  if (ptr != end) return NumberStatus::NotANumber;
  if (ec == std::errc::result_out_of_range)
    return order_of_magnitude_negative(tok) ? NumberStatus::TooSmall : NumberStatus::OutOfRange;
  if (ec != std::errc()) return NumberStatus::NotANumber;
  return NumberStatus::Ok;
}

// The value of one unit in the last digit of a number as printed: "0.0333"
// -> 1e-4, "3.33e-02" -> 1e-4, "12" -> 1, "1.5E+1" -> 1. The token has
// already been read as a number (finite_number).
// The exponent of a number as printed, after its 'e', 'E', 'd' or 'D'
// (sign included); empty without one.
std::string_view exponent_text(std::string_view tok) {
  const std::size_t at = tok.find_first_of("eEdD");
  return at == std::string_view::npos ? std::string_view() : tok.substr(at + 1);
}

double printed_resolution(std::string_view tok) {
  const std::string_view mantissa = tok.substr(0, tok.find_first_of("eEdD"));
  int exponent = 0;
  if (std::string_view e = exponent_text(tok); !e.empty()) {
    if (e.front() == '+') e.remove_prefix(1);
    std::from_chars(e.data(), e.data() + e.size(), exponent);
  }
  const std::size_t dot = mantissa.find('.');
  const int decimals = dot == std::string_view::npos ? 0 : int(mantissa.size() - dot - 1);
  return std::pow(10.0, double(exponent - decimals));
}

// Why a number that rounds to 0 is refused. Subnormals (down to about
// 4.9e-324) are read; below them a value is refused rather than read as 0,
// as the case file's numbers are: no record holds one, a mistyped exponent
// does.
std::string too_small_problem(std::string_view tok) {
  return quoted(tok) + ", which is too small in magnitude to represent (below about 4.9e-324, the smallest "
                       "double): a mistyped exponent?";
}

// Parses `tok` as a finite double or throws an InputError for `field`.
double finite_number(const std::string& file, int line_no, const char* field, std::string_view tok,
                     const std::string& what) {
  double v = 0.0;
  const NumberStatus st = parse_number(tok, v);
  if (st == NumberStatus::NotANumber)
    throw InputError(file, line_no, field, "expected " + what + ", got " + quoted(tok));
  if (st == NumberStatus::TooSmall)
    throw InputError(file, line_no, field, "expected " + what + ", got " + too_small_problem(tok));
  if (st == NumberStatus::OutOfRange || !std::isfinite(v))
    throw InputError(file, line_no, field, "expected " + what + " (finite), got " + quoted(tok));
  return v;
}

// ---- AT2 header line 4 -------------------------------------------------------

// Value after "<keyword> =" in `line`, searching from `from`. Returns false if
// no keyword is followed by '='. `value` stops at a blank or comma; `after` is
// the index just past it.
bool keyword_value(std::string_view line, std::string_view keyword, std::size_t from, std::string_view& value,
                   std::size_t& after) {
  std::size_t k = from;
  std::size_t i = 0;
  for (;; k += 1) {
    k = find_ci(line, keyword, k);
    if (k == std::string_view::npos) return false;
    // Whole word only: "DT" must not match inside another word.
    if (k > 0 && is_alpha(line[k - 1])) continue;
    i = k + keyword.size();
    while (i < line.size() && is_blank(line[i])) ++i;
    // The word without '=' is not this keyword ("NPTS, DT"); one with it
    // may still follow (a repeated key is found so).
    if (i < line.size() && line[i] == '=') break;
  }
  ++i;
  while (i < line.size() && is_blank(line[i])) ++i;
  std::size_t j = i;
  while (j < line.size() && !is_blank(line[j]) && line[j] != ',') ++j;
  value = line.substr(i, j - i);
  after = j;
  return true;
}

struct At2Size {
  long long npts = 0;
  double dt_s = 0.0;
};

// The layouts of header line 4 that are read, shown when the line is not
// one of them, so the message says how to fix the file.
constexpr const char* kLineFourLayouts =
    "the layouts read are 'NPTS= 5372, DT= .0100 SEC' (NGA; the two in either order, keywords in any case, "
    "commas optional), '5372  .0100  NPTS, DT' (older PEER files: the numbers, then their names in the same "
    "order) and '5372 .0100' (a whole number of samples, then the time step in s with a decimal point)";

// NPTS from its token on line 4, whatever the layout: a whole number >= 2.
long long npts_value(const std::string& file, std::string_view tok) {
  constexpr int kLine = 4;
  long long npts = 0;
  // std::from_chars reads no '+' sign, which the layouts allow ("+100" was
  // refused as "expected a whole number"; review probe).
  std::string_view digits = tok;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  const char* const end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, npts);
  if (ec == std::errc::result_out_of_range && ptr == end)
    throw InputError(file, kLine, "NPTS", "expected a number of samples a record can hold, got " + quoted(tok));
  if (ec != std::errc() || ptr != end)
    throw InputError(file, kLine, "NPTS", "expected a whole number of samples, got " + quoted(tok));
  if (npts <= 0) throw InputError(file, kLine, "NPTS", "expected a positive number of samples, got " + quoted(tok));
  if (npts < 2)
    throw InputError(file, kLine, "NPTS",
                     "expected at least 2 samples (one interval defines the time step), got " + quoted(tok));
  return npts;
}

bool equals_ci(std::string_view a, std::string_view b) { return a.size() == b.size() && find_ci(a, b) == 0; }

// The unit written after DT's value, glued (".0200SEC") or as the next word
// ("DT= .0200 SEC"), must be seconds: any other was ignored, and
// "DT= .5 MSEC" ran a record 1000 times too slow. Brackets and a trailing
// '.' are punctuation ("(s)", "sec."); no unit at all means seconds.
void check_dt_unit(const std::string& file, std::string_view unit, std::string_view shown_line) {
  std::string_view word = unit;
  if (!word.empty() && (word.front() == '(' || word.front() == '[')) word.remove_prefix(1);
  if (!word.empty() && word.back() == '.') word.remove_suffix(1);
  if (!word.empty() && (word.back() == ')' || word.back() == ']')) word.remove_suffix(1);
  for (const char* seconds : {"SEC", "SECS", "S", "SECONDS"})
    if (equals_ci(word, seconds)) return;
  throw InputError(file, 4, "DT",
                   "expected the time step in seconds (unit SEC, SECS, S, SECONDS or none) on header line 4, got "
                   "unit " +
                       quoted(unit) + " in " + std::string(shown_line) + ": convert DT to s");
}

// The word after DT's value in the keyword layout ("SEC" in "DT= .02 SEC,"):
// up to a blank, comma or '='; empty if the value ends its item (a comma,
// the line's end), the next word is a keyword ("DT= .02 NPTS= 5") or it
// holds no letter (punctuation names no unit; "µs" is a unit).
std::string_view word_after_value(std::string_view line, std::size_t after) {
  std::size_t i = after;
  while (i < line.size() && is_blank(line[i])) ++i;
  std::size_t j = i;
  while (j < line.size() && !is_blank(line[j]) && line[j] != ',' && line[j] != '=') ++j;
  std::size_t k = j;
  while (k < line.size() && is_blank(line[k])) ++k;
  if (k < line.size() && line[k] == '=') return {};
  const std::string_view word = line.substr(i, j - i);
  const bool has_letter = std::any_of(word.begin(), word.end(), [](char c) {
    return is_alpha(c) || static_cast<unsigned char>(c) >= 0x80;
  });
  return has_letter ? word : std::string_view();
}

// DT from its token on line 4, whatever the layout: a positive finite time
// step in s within the sampling bounds. A unit glued to the number
// (".0200SEC") is checked by check_dt_unit.
double dt_value(const std::string& file, std::string_view tok, std::string_view shown_line) {
  constexpr int kLine = 4;
  // The letters ending a token that starts as a number ("nan" does not).
  std::string_view number = tok;
  while (!number.empty() && is_alpha(number.back())) number.remove_suffix(1);
  const char last = number.empty() ? '\0' : number.back();
  if (number.size() < tok.size() && ((last >= '0' && last <= '9') || last == '.')) {
    check_dt_unit(file, tok.substr(number.size()), shown_line);
  } else {
    number = tok;
  }
  double dt = 0.0;
  const NumberStatus st = parse_number(number, dt);
  if (st != NumberStatus::Ok || !std::isfinite(dt) || dt <= 0.0)
    throw InputError(file, kLine, "DT", "expected a positive finite time step in s, got " + quoted(tok));
  if (const std::string why = sample_interval_problem(dt); !why.empty()) throw InputError(file, kLine, "DT", why);
  return dt;
}

// A token written as a whole number: digits with an optional sign.
bool is_whole_number_text(std::string_view tok) {
  if (!tok.empty() && (tok.front() == '+' || tok.front() == '-')) tok.remove_prefix(1);
  return !tok.empty() && std::all_of(tok.begin(), tok.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Header line 4 in one of the layouts of kLineFourLayouts:
//   keywords   "NPTS= 5372, DT= .0100 SEC" or "DT= .0100 SEC, NPTS= 5372"
//              (either keyword followed by '=' selects this layout);
//   labelled   "5372  .0100  NPTS, DT" (or "... DT, NPTS" with the numbers
//              swapped): two numbers, then their names, blanks or commas
//              between;
//   bare       "5372 .0100": read only when unambiguous, a whole number
//              then a number with a decimal point or exponent ("5372 1"
//              or ".0100 5372" could be either way round and is refused).
// Every layout's values get the same checks and messages (npts_value,
// dt_value).
At2Size parse_npts_dt(const std::string& file, std::string_view line) {
  constexpr int kLine = 4;
  const std::string shown = quoted(trim(line));
  std::string_view npts_tok, dt_tok;
  std::size_t npts_after = 0, dt_after = 0;
  const bool npts_keyword = keyword_value(line, "NPTS", 0, npts_tok, npts_after);
  const bool dt_keyword = keyword_value(line, "DT", 0, dt_tok, dt_after);
  if (npts_keyword || dt_keyword) {
    // A key given twice left its second value unread ("NPTS= 6, DT= .01
    // SEC, NPTS= 7" read 6): which one is meant, only the file's author knows.
    for (const auto& [key, found, after] : {std::tuple{"NPTS", npts_keyword, npts_after},
                                            std::tuple{"DT", dt_keyword, dt_after}}) {
      std::string_view again;
      std::size_t again_after = 0;
      if (found && keyword_value(line, key, after, again, again_after))
        throw InputError(file, kLine, key,
                         std::string("expected ").append(key).append("= once on header line 4, got it twice in ")
                             .append(shown));
    }
    // A second number after a key's value ("DT= .02 .01 SEC") was left
    // unread, and the record played at the first (input probe, stop 41:
    // half speed): which one is meant, only the file's author knows.
    for (const auto& [key, found, tok, after] :
         {std::tuple{"NPTS", npts_keyword, npts_tok, npts_after}, std::tuple{"DT", dt_keyword, dt_tok, dt_after}}) {
      if (!found || tok.empty()) continue;
      std::size_t i = after;
      while (i < line.size() && is_blank(line[i])) ++i;
      std::size_t j = i;
      while (j < line.size() && !is_blank(line[j]) && line[j] != ',' && line[j] != '=') ++j;
      double second = 0.0;
      if (j > i && parse_number(line.substr(i, j - i), second) == NumberStatus::Ok)
        throw InputError(file, kLine, key,
                         std::string("expected one value after ").append(key).append("=, got ")
                             .append(quoted(line.substr(after - tok.size(), j - (after - tok.size()))))
                             .append(" in ")
                             .append(shown));
    }
    // A value of digits with a comma and more digits after it ("DT= 0,0100",
    // "NPTS= 5,372") is a decimal comma or a thousands separator, which the
    // comma between the keys cut short: quoted whole, not as its first part
    // (a probe's "DT= 0,0100" was refused as "got '0'").
    for (const auto& [key, found, tok, after, expected, hint] :
         {std::tuple{"DT", dt_keyword, dt_tok, dt_after, "a time step in s with a decimal point",
                     " (a decimal comma? write the time step with a point, as .0100)"},
          std::tuple{"NPTS", npts_keyword, npts_tok, npts_after, "the number of samples",
                     " (a thousands separator? write the count in digits only, as 5372)"}}) {
      if (!found || tok.empty() || after + 1 >= line.size() || line[after] != ',') continue;
      const char next = line[after + 1];
      if (!(next >= '0' && next <= '9') || !std::all_of(tok.begin(), tok.end(), [](char c) {
            return (c >= '0' && c <= '9') || c == '.' || c == '+' || c == '-';
          }))
        continue;
      std::size_t end = after + 1;
      while (end < line.size() && line[end] >= '0' && line[end] <= '9') ++end;
      throw InputError(file, kLine, key,
                       std::string("expected ").append(expected).append(", got ").append(
                           quoted(line.substr(after - tok.size(), end - (after - tok.size())))).append(hint));
    }
    if (!npts_keyword || npts_tok.empty())
      throw InputError(file, kLine, "NPTS",
                       std::string("expected 'NPTS= <number of samples>' with 'DT= <time step> SEC' on header line "
                                   "4, got ")
                           .append(shown)
                           .append("; ")
                           .append(kLineFourLayouts));
    if (!dt_keyword || dt_tok.empty())
      throw InputError(file, kLine, "DT",
                       std::string("expected 'DT= <time step> SEC' with 'NPTS= <number of samples>' on header line "
                                   "4, got ")
                           .append(shown)
                           .append("; ")
                           .append(kLineFourLayouts));
    if (const std::string_view unit = word_after_value(line, dt_after); !unit.empty())
      check_dt_unit(file, unit, shown);
  } else {
    const std::vector<std::string_view> tokens = split_words(line, ",");
    if (tokens.size() == 4 && equals_ci(tokens[2], "NPTS") && equals_ci(tokens[3], "DT")) {
      npts_tok = tokens[0];
      dt_tok = tokens[1];
    } else if (tokens.size() == 4 && equals_ci(tokens[2], "DT") && equals_ci(tokens[3], "NPTS")) {
      dt_tok = tokens[0];
      npts_tok = tokens[1];
    } else if (tokens.size() == 2 && is_whole_number_text(tokens[0]) && !is_whole_number_text(tokens[1])) {
      npts_tok = tokens[0];
      dt_tok = tokens[1];
    } else {
      throw InputError(file, kLine, "NPTS",
                       std::string("expected the number of samples (NPTS) and the time step (DT) on header line 4, "
                                   "got ")
                           .append(shown)
                           .append("; ")
                           .append(kLineFourLayouts));
    }
  }
  At2Size out;
  out.npts = npts_value(file, npts_tok);
  out.dt_s = dt_value(file, dt_tok, shown);
  return out;
}

// If line 3 names units ("... IN UNITS OF G"), they must be g: PEER writes
// velocity (.VT2) and displacement (.DT2) files in the same layout, and
// reading one as acceleration would be silently wrong by orders of magnitude.
//
// Without "UNITS OF" the line is still read for what it names (input probe,
// stop 41: "VELOCITY TIME SERIES" and "ACCELERATION IN CM/S/S" were read as
// acceleration in g): a quantity word other than acceleration
// (VELOCITY, DISPLACEMENT) with no ACCELERATION beside it, or a word that
// is a unit of length per time (is_rate_unit: CM/S/S, M/S2, CM/SEC, ...;
// GAL, GALS), is refused. Other words with a '/' ("N/S", "CDMG/USGS",
// dates) are text.
bool is_rate_unit(std::string_view word) {
  const std::size_t slash = word.find('/');
  if (slash == std::string_view::npos) return equals_ci(word, "GAL") || equals_ci(word, "GALS");
  const std::string_view length = word.substr(0, slash);
  bool length_unit = false;
  for (const char* l : {"MM", "CM", "M", "IN", "FT"}) length_unit = length_unit || equals_ci(length, l);
  if (!length_unit) return false;
  // The time part: S or SEC, optionally squared (2, ^2, **2) or divided by
  // S or SEC again.
  std::string_view rest = word.substr(slash + 1);
  bool time_unit = false;
  for (const char* t : {"SEC", "S"})
    if (!time_unit && find_ci(rest, t) == 0) {
      rest.remove_prefix(std::string_view(t).size());
      time_unit = true;
    }
  if (!time_unit) return false;
  if (rest.empty() || rest == "2" || rest == "^2" || rest == "**2") return true;
  return equals_ci(rest, "/S") || equals_ci(rest, "/SEC");
}

void check_at2_units(const std::string& file, std::string_view line) {
  const std::size_t k = find_ci(line, "UNITS OF");
  if (k == std::string_view::npos) {
    bool acceleration = false;
    std::string_view other_quantity, other_unit;
    for (std::string_view word : split_words(line, ",()[]:;")) {
      if (word.back() == '.') word.remove_suffix(1);
      if (word.empty()) continue;
      if (find_ci(word, "ACCEL") == 0) acceleration = true;
      if (equals_ci(word, "VELOCITY") || equals_ci(word, "DISPLACEMENT")) other_quantity = word;
      if (is_rate_unit(word)) other_unit = word;
    }
    if (!other_quantity.empty() && !acceleration)
      throw InputError(file, 3, "header",
                       "expected an acceleration record (line 3 as 'ACCELERATION TIME SERIES IN UNITS OF G'), got "
                       "a line naming " +
                           quoted(other_quantity) + ": " + quoted(trim(line)) +
                           " (a PEER velocity or displacement file?)");
    if (!other_unit.empty())
      throw InputError(file, 3, "header",
                       "expected acceleration in g in a peer_at2 file (line 3 as 'ACCELERATION TIME SERIES IN UNITS "
                       "OF G'), got unit " +
                           quoted(other_unit) + " in " + quoted(trim(line)) +
                           ": a record in another unit reads as format two_column with its unit (g, m/s2 or cm/s2)");
    return;
  }
  std::size_t i = k + 8;
  while (i < line.size() && is_blank(line[i])) ++i;
  std::size_t j = i;
  while (j < line.size() && !is_blank(line[j]) && line[j] != ',') ++j;
  const std::string_view unit = line.substr(i, j - i);
  if (!(unit.size() == 1 && to_upper(unit[0]) == 'G'))
    throw InputError(file, 3, "header",
                     "expected acceleration 'IN UNITS OF G' on header line 3, got units " + quoted(unit) +
                         " (a PEER velocity or displacement file?)");
}

// ---- two-column fields -------------------------------------------------------

// Why a two-column line may have split into more columns, for its message
// (input probe, stop 41: "0,00;0,009792" and a quoted CSV header read
// "found 3" and "found 4" with no hint): a header line (a field that is
// not a number and holds a letter or a quote), or numbers written with
// decimal commas (a semicolon between them, or two blank-separated words
// each with a comma between digits). A line of three numbers gets none.
std::string extra_columns_hint(std::string_view body) {
  for (const std::string_view w : split_words(body, ",;")) {
    double value = 0.0;
    if (parse_number(w, value) == NumberStatus::Ok) continue;
    if (std::any_of(w.begin(), w.end(), [](char c) { return c == '"' || c == '\'' || is_alpha(c); }))
      return " (a header line? start it with '#')";
  }
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  int comma_words = 0;  // blank- or semicolon-separated words with a comma between digits
  for (const std::string_view w : split_words(body, ";"))
    for (std::size_t k = 1; k + 1 < w.size(); ++k)
      if (w[k] == ',' && digit(w[k - 1]) && digit(w[k + 1])) {
        ++comma_words;
        break;
      }
  if (body.find(';') != std::string_view::npos || comma_words >= 2)
    return " (numbers with decimal commas? write them with a point, as 0.009792, and separate the two columns by "
           "blanks or one comma)";
  return "";
}

// Splits a data line into fields separated by blanks and/or one comma.
// Returns the number of fields found (up to `max_fields` are stored), or -1
// if a field is empty (two commas in a row, or a leading/trailing comma).
int split_fields(std::string_view line, std::string_view* fields, int max_fields) {
  int n = 0;
  std::size_t i = 0;
  const std::size_t size = line.size();
  while (i < size && is_blank(line[i])) ++i;
  while (i < size) {
    std::size_t j = i;
    while (j < size && !is_blank(line[j]) && line[j] != ',') ++j;
    if (j == i) return -1;  // a comma where a field should start
    if (n < max_fields) fields[n] = line.substr(i, j - i);
    ++n;
    i = j;
    while (i < size && is_blank(line[i])) ++i;
    if (i < size && line[i] == ',') {
      ++i;
      while (i < size && is_blank(line[i])) ++i;
      if (i >= size) return -1;  // trailing comma
    }
  }
  return n;
}

}  // namespace

// ---- names -------------------------------------------------------------------

bool parse_record_format(const std::string& name, RecordFormat& out) {
  if (name == "peer_at2") {
    out = RecordFormat::PeerAt2;
    return true;
  }
  if (name == "two_column") {
    out = RecordFormat::TwoColumn;
    return true;
  }
  return false;
}

const char* record_format_name(RecordFormat f) {
  switch (f) {
    case RecordFormat::PeerAt2:
      return "peer_at2";
    case RecordFormat::TwoColumn:
      return "two_column";
  }
  return "unknown";
}

bool parse_acceleration_unit(const std::string& name, AccelerationUnit& out) {
  if (name == "g") {
    out = AccelerationUnit::G;
    return true;
  }
  if (name == "m/s2") {
    out = AccelerationUnit::MetrePerSecond2;
    return true;
  }
  if (name == "cm/s2") {
    out = AccelerationUnit::CentimetrePerSecond2;
    return true;
  }
  return false;
}

const char* acceleration_unit_name(AccelerationUnit u) {
  switch (u) {
    case AccelerationUnit::G:
      return "g";
    case AccelerationUnit::MetrePerSecond2:
      return "m/s2";
    case AccelerationUnit::CentimetrePerSecond2:
      return "cm/s2";
  }
  return "unknown";
}

double acceleration_unit_to_mps2(AccelerationUnit u) {
  switch (u) {
    case AccelerationUnit::G:
      return kStandardGravity_mps2;
    case AccelerationUnit::MetrePerSecond2:
      return 1.0;
    case AccelerationUnit::CentimetrePerSecond2:
      return 0.01;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// ---- PEER .AT2 ---------------------------------------------------------------

namespace {
// Digits of a number's exponent ("-.1790158E-02" -> 2), -1 without one.
int exponent_digits(std::string_view tok) {
  if (tok.find_first_of("eEdD") == std::string_view::npos) return -1;
  std::string_view e = exponent_text(tok);
  if (!e.empty() && (e.front() == '+' || e.front() == '-')) e.remove_prefix(1);
  return int(e.size());
}
}  // namespace

AccelerationRecord read_peer_at2(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string text = load_file(file, "a PEER .AT2 accelerogram (4 header lines, then NPTS values in g)");

  LineCursor cursor(text);
  std::string_view header[4];
  for (int i = 0; i < 4; ++i) {
    if (!cursor.next(header[i]))
      throw InputError(name, i + 1, "header",
                       "expected 4 header lines (banner, event/station/component, units, NPTS and DT); the file "
                       "ends after line " +
                           std::to_string(i));
    require_text(name, i + 1, header[i], "header");
  }
  check_at2_units(name, header[2]);
  const At2Size size = parse_npts_dt(name, header[3]);

  AccelerationRecord rec;
  rec.source = name;
  // Header text goes into summary.json, warnings and messages as UTF-8;
  // older and Windows-written files carry Latin-1 ("D\xfczce, Turkey").
  rec.description = utf8_from_utf8_or_latin1(trim(header[1]));
  rec.dt_s = size.dt_s;
  // Never trust NPTS for the allocation alone: a corrupt header must not
  // request gigabytes. Each value takes at least two bytes (digit + space).
  rec.acceleration_mps2.reserve(static_cast<std::size_t>(std::min<long long>(size.npts, static_cast<long long>(text.size() / 2 + 1))));

  const long long npts = size.npts;
  long long count = 0;
  int first_surplus_line = 0;
  // PEER writes every value in one Fortran format (E15.7: two exponent
  // digits). A download cut inside its last value can still hold NPTS
  // values, the last one 10 or 100 times off ("-.1790158E-0" for E-02): a
  // last exponent shorter than every other one is refused.
  int exponent_width = -2;  // -2: not seen yet; -1: the values differ or have none
  std::string_view last_value;  // a view into `text`, which outlives the loop
  int last_value_line = 0;
  std::string_view line;
  while (cursor.next(line)) {
    const int line_no = cursor.line_no();
    require_text(name, line_no, line, "value");
    std::size_t i = 0;
    const std::size_t n = line.size();
    while (true) {
      while (i < n && is_blank(line[i])) ++i;
      if (i >= n) break;
      std::size_t j = i;
      while (j < n && !is_blank(line[j])) ++j;
      const std::string_view tok = line.substr(i, j - i);
      i = j;
      ++count;
      if (count > npts) {
        // Keep counting so the message can say how many values there are.
        if (first_surplus_line == 0) first_surplus_line = line_no;
        continue;
      }
      double v = 0.0;
      const NumberStatus st = parse_number(tok, v);
      if (st == NumberStatus::TooSmall)
        throw InputError(name, line_no, "value",
                         "expected a number (value " + std::to_string(count) + " of NPTS=" +
                             std::to_string(npts) + ", in g), got " + too_small_problem(tok));
      if (st != NumberStatus::Ok || !std::isfinite(v))
        throw InputError(name, line_no, "value",
                         "expected a finite number (value " + std::to_string(count) + " of NPTS=" +
                             std::to_string(npts) + ", in g), got " + quoted(tok));
      if (!last_value.empty()) {  // the value before this one was not the last
        const int digits = exponent_digits(last_value);
        exponent_width = exponent_width == -2 || exponent_width == digits ? digits : -1;
      }
      last_value = tok;
      last_value_line = line_no;
      if (const std::string why = acceleration_problem(v, kStandardGravity_mps2); !why.empty())
        throw InputError(name, line_no, "value",
                         "value " + std::to_string(count) + " of NPTS=" + std::to_string(npts) + ", " + quoted(tok) +
                             ": " + why);
      rec.acceleration_mps2.push_back(v * kStandardGravity_mps2);
    }
  }
  if (count != npts) {
    const int at_line = count > npts ? first_surplus_line : cursor.line_no();
    const std::string where = count > npts ? " (the first surplus value is on this line)"
                                           : " (the data end at this line)";
    throw InputError(name, at_line, "NPTS",
                     "header line 4 declares NPTS=" + std::to_string(npts) + " but the file holds " +
                         std::to_string(count) + " values; expected " + std::to_string(npts) + where);
  }
  if (exponent_width >= 1 && exponent_digits(last_value) < exponent_width)
    throw InputError(name, last_value_line, "value",
                     "expected the last value's exponent to have " + std::to_string(exponent_width) +
                         " digits like every other value's, got " + quoted(last_value) +
                         ": the file looks cut inside its last value; fetch it again");
  return rec;
}

// ---- two-column text ---------------------------------------------------------

AccelerationRecord read_two_column(const std::filesystem::path& file, AccelerationUnit unit) {
  const std::string name = file.string();
  const std::string text = load_file(file, "a two-column text accelerogram (time in s, acceleration)");
  const double to_mps2 = acceleration_unit_to_mps2(unit);
  const std::string unit_name = acceleration_unit_name(unit);

  std::vector<double> time_s;
  std::vector<double> accel_mps2;
  time_s.reserve(text.size() / 8 + 1);  // a row takes at least "t a\n" with real numbers
  accel_mps2.reserve(text.size() / 8 + 1);

  std::string first_comment;
  bool have_comment = false;
  int prev_line = 0;
  double first_interval_s = 0.0;
  double min_interval_s = std::numeric_limits<double>::infinity();
  double max_interval_s = 0.0;
  int min_interval_line = 0;
  int max_interval_line = 0;
  bool uniform = true;
  double time_resolution_s = 0.0;  // the coarsest last printed digit of a time (s)
  // Relative tolerance for "uniform", from the task definition: far above the
  // rounding of times printed with 7+ significant digits on records of ~1e4
  // samples, far below any deliberate change of sampling rate.
  constexpr double kUniformRelTol = 1e-6;

  LineCursor cursor(text);
  std::string_view line;
  while (cursor.next(line)) {
    const int line_no = cursor.line_no();
    require_text(name, line_no, line, "value");
    const std::string_view body = trim(line);
    if (body.empty()) continue;
    if (body.front() == '#') {
      if (!have_comment) {
        first_comment = utf8_from_utf8_or_latin1(trim(body.substr(1)));  // as an AT2 header's text
        have_comment = !first_comment.empty();
      }
      continue;
    }
    std::string_view fields[2];
    const int n_fields = split_fields(body, fields, 2);
    if (n_fields < 0)
      throw InputError(name, line_no, "value",
                       "expected 'time acceleration' separated by blanks or one comma, found an empty field in " +
                           quoted(body));
    if (n_fields == 1)
      throw InputError(name, line_no, "acceleration",
                       "expected 2 columns 'time acceleration', found 1: " + quoted(body));
    if (n_fields > 2)
      throw InputError(name, line_no, "value",
                       "expected 2 columns 'time acceleration', found " + std::to_string(n_fields) + ": " +
                           quoted(body) + extra_columns_hint(body));
    const double t = finite_number(name, line_no, "time", fields[0], "a time in s");
    time_resolution_s = std::max(time_resolution_s, printed_resolution(fields[0]));
    const double a = finite_number(name, line_no, "acceleration", fields[1], "an acceleration in " + unit_name);
    if (!time_s.empty()) {
      const double h = t - time_s.back();
      if (!(h > 0.0))
        throw InputError(name, line_no, "time",
                         "expected a time greater than " + fmt(time_s.back()) + " s (line " +
                             std::to_string(prev_line) + "): times must increase strictly, got " + quoted(fields[0]));
      if (time_s.size() == 1) first_interval_s = h;
      if (std::abs(h - first_interval_s) > kUniformRelTol * first_interval_s) uniform = false;
      if (h > max_interval_s) {
        max_interval_s = h;
        max_interval_line = line_no;
      }
      if (h < min_interval_s) {
        min_interval_s = h;
        min_interval_line = line_no;
      }
    }
    time_s.push_back(t);
    if (const std::string why = acceleration_problem(a, to_mps2); !why.empty())
      throw InputError(name, line_no, "acceleration", quoted(fields[1]) + " " + unit_name + ": " + why);
    accel_mps2.push_back(a * to_mps2);
    prev_line = line_no;
  }
  if (time_s.size() < 2)
    throw InputError(name, cursor.line_no(), "value",
                     "expected at least 2 samples (rows 'time acceleration'), found " + std::to_string(time_s.size()));

  const std::size_t n = time_s.size();
  const double t0 = time_s.front();
  const double span_s = time_s.back() - t0;

  AccelerationRecord rec;
  rec.source = name;
  rec.file_start_time_s = t0;
  std::string notes = "two-column text, acceleration in " + unit_name;
  if (t0 != 0.0)
    notes += "; times shifted by " + fmt(-t0) + " s so the first sample (t = " + fmt(t0) +
             " s in the file) is at t = 0";

  // The shortest and the longest interval must both be a sampling interval.
  if (const std::string why = sample_interval_problem(min_interval_s); !why.empty())
    throw InputError(name, min_interval_line, "time", "the interval ending on this line: " + why);
  if (const std::string why = sample_interval_problem(max_interval_s); !why.empty())
    throw InputError(name, max_interval_line, "time", "the interval ending on this line: " + why);
  // Times printed to fewer digits than the interval needs (1/300 s to four
  // decimals: intervals of 0.0033 and 0.0034 s) are uniform sampling when
  // every time is within one unit of its last printed digit of the grid
  // t_0 + k (t_last - t_0) / (n - 1); read as non-uniform, their samples
  // would be placed up to half a digit off that grid.
  double grid_deviation_s = 0.0;
  if (!uniform) {
    const double mean_interval_s = span_s / double(n - 1);
    for (std::size_t k = 0; k < n; ++k)
      grid_deviation_s = std::max(grid_deviation_s, std::abs(time_s[k] - (t0 + double(k) * mean_interval_s)));
    if (grid_deviation_s <= time_resolution_s * (1.0 + 1e-9) && time_resolution_s < 0.5 * mean_interval_s) {
      uniform = true;
      notes += "; times printed to " + fmt(time_resolution_s) + " s read as uniform sampling (within " +
               fmt(grid_deviation_s) + " s of a uniform grid)";
    }
  }
  if (uniform) {
    rec.dt_s = span_s / double(n - 1);
    rec.acceleration_mps2 = std::move(accel_mps2);
  } else {
    const double mean_interval_s = span_s / double(n - 1);
    // See the header: a hundredfold range of intervals is a typo, not a record.
    constexpr double kMaxIntervalRatio = 100.0;
    if (mean_interval_s > kMaxIntervalRatio * min_interval_s)
      throw InputError(name, min_interval_line, "time",
                       "expected roughly uniform sampling: the interval ending on this line, " +
                           fmt(min_interval_s) + " s, is more than " + fmt(kMaxIntervalRatio) +
                           " times smaller than the mean interval " + fmt(mean_interval_s) +
                           " s (a mistyped time?)");
    // The samples are kept where they are: linear interpolation between
    // them is exact for the trace the file describes, and every sample,
    // peaks included, stays a value of the record.
    rec.dt_s = min_interval_s;
    rec.sample_time_s.resize(n);
    for (std::size_t k = 0; k < n; ++k) rec.sample_time_s[k] = time_s[k] - t0;
    rec.sample_time_s[0] = 0.0;
    rec.acceleration_mps2 = std::move(accel_mps2);
    notes += "; non-uniform sampling (" + std::to_string(n) + " samples, intervals " + fmt(min_interval_s) + " to " +
             fmt(max_interval_s) + " s) kept as given, linear between samples";
  }
  rec.description = have_comment ? first_comment + " [" + notes + "]" : notes;
  return rec;
}

AccelerationRecord read_accelerogram(const std::filesystem::path& file, RecordFormat format,
                                     AccelerationUnit two_column_unit) {
  switch (format) {
    case RecordFormat::PeerAt2:
      return read_peer_at2(file);
    case RecordFormat::TwoColumn:
      return read_two_column(file, two_column_unit);
  }
  throw InputError(file.string(), 0, "format", "expected peer_at2 or two_column");
}

std::string scaled_record_problem(const AccelerationRecord& record, double amplitude_scale) {
  const double peak_g = std::abs(record.peak_mps2()) / kStandardGravity_mps2;
  if (!(peak_g * amplitude_scale > kMaxAbsAcceleration_g)) return "";
  std::ostringstream why;
  why << "amplitude scale " << amplitude_scale << " takes the record's peak of " << peak_g << " g to "
      << peak_g * amplitude_scale << " g, more than " << kMaxAbsAcceleration_g
      << " g (five times the largest ground acceleration ever recorded): a scale meant as a percentage, or a "
         "typing error?";
  return why.str();
}

}  // namespace fq
