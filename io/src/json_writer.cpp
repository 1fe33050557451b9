#include "io/json_writer.h"

#include <cmath>
#include <stdexcept>

#include "io/utf8_text.h"
#include "number_format.h"

namespace fq {

JsonWriter::JsonWriter(int indent_spaces) : indent_(indent_spaces < 0 ? 0 : indent_spaces) {}

std::string JsonWriter::quote(std::string_view text) {
  static const char* const hex = "0123456789abcdef";
  // JSON is UTF-8 (RFC 8259 section 8.1): a byte that is not, from a record
  // header or a path, made a whole summary.json unreadable to strict
  // readers (Python's json); it is written as U+FFFD instead.
  const bool valid = is_valid_utf8(text);
  const std::string repaired = valid ? std::string() : utf8_repaired(text);
  const std::string_view s = valid ? text : std::string_view(repaired);
  std::string out;
  out.reserve(s.size() + 2);
  out.push_back('"');
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) {
          out += "\\u00";
          out.push_back(hex[c >> 4]);
          out.push_back(hex[c & 0xF]);
        } else {
          out.push_back(ch);
        }
    }
  }
  out.push_back('"');
  return out;
}

std::string JsonWriter::number(double x) { return std::isfinite(x) ? detail::format_number(x) : std::string("null"); }

void JsonWriter::newline() {
  if (indent_ == 0) return;
  out_.push_back('\n');
  out_.append(stack_.size() * std::size_t(indent_), ' ');
}

// Comma, newline and indentation before a value (or before a key in an object).
void JsonWriter::before_value() {
  if (stack_.empty()) {
    if (wrote_root_) throw std::logic_error("JsonWriter: a second top-level value");
    wrote_root_ = true;
    return;
  }
  Level& top = stack_.back();
  if (top.is_object) {
    if (!top.key_pending) throw std::logic_error("JsonWriter: value in an object without a key");
    top.key_pending = false;
    return;  // key() already placed comma and indentation
  }
  if (top.count++ > 0) out_.push_back(',');
  newline();
}

JsonWriter& JsonWriter::key(std::string_view name) {
  if (stack_.empty() || !stack_.back().is_object) throw std::logic_error("JsonWriter: key outside an object");
  Level& top = stack_.back();
  if (top.key_pending) throw std::logic_error("JsonWriter: two keys in a row");
  if (top.count++ > 0) out_.push_back(',');
  newline();
  out_ += quote(name);
  out_ += indent_ == 0 ? ":" : ": ";
  top.key_pending = true;
  return *this;
}

JsonWriter& JsonWriter::begin_object() {
  before_value();
  out_.push_back('{');
  stack_.push_back({true, 0, false});
  return *this;
}

JsonWriter& JsonWriter::end_object() {
  if (stack_.empty() || !stack_.back().is_object || stack_.back().key_pending)
    throw std::logic_error("JsonWriter: end_object without a matching begin_object (or after a bare key)");
  const bool had_members = stack_.back().count > 0;
  stack_.pop_back();
  if (had_members) newline();
  out_.push_back('}');
  return *this;
}

JsonWriter& JsonWriter::begin_array() {
  before_value();
  out_.push_back('[');
  stack_.push_back({false, 0, false});
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  if (stack_.empty() || stack_.back().is_object)
    throw std::logic_error("JsonWriter: end_array without a matching begin_array");
  const bool had_members = stack_.back().count > 0;
  stack_.pop_back();
  if (had_members) newline();
  out_.push_back(']');
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view s) {
  before_value();
  out_ += quote(s);
  return *this;
}

JsonWriter& JsonWriter::value(double x) {
  before_value();
  out_ += number(x);
  return *this;
}

JsonWriter& JsonWriter::value(bool b) {
  before_value();
  out_ += b ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::integer(std::int64_t i) {
  before_value();
  detail::append_integer(out_, i);
  return *this;
}

JsonWriter& JsonWriter::null() {
  before_value();
  out_ += "null";
  return *this;
}

JsonWriter& JsonWriter::raw(std::string_view json_value) {
  if (!json_is_valid(json_value))
    throw std::invalid_argument("JsonWriter: not a valid JSON value: " + std::string(json_value.substr(0, 80)));
  before_value();
  // Trim surrounding whitespace so the indentation stays tidy.
  const auto first = json_value.find_first_not_of(" \t\r\n");
  const auto last = json_value.find_last_not_of(" \t\r\n");
  out_.append(json_value.substr(first, last - first + 1));
  return *this;
}

// ---- validator: recursive descent over RFC 8259's grammar -------------------
namespace {

class JsonChecker {
 public:
  explicit JsonChecker(std::string_view t) : t_(t) {}

  bool document() {
    skip_ws();
    if (!value(0)) return false;
    skip_ws();
    return i_ == t_.size();
  }

 private:
  static constexpr int kMaxDepth = 256;

  bool at_end() const { return i_ >= t_.size(); }
  char peek() const { return at_end() ? '\0' : t_[i_]; }
  void skip_ws() {
    while (!at_end() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\n' || t_[i_] == '\r')) ++i_;
  }
  bool literal(std::string_view word) {
    if (t_.substr(i_, word.size()) != word) return false;
    i_ += word.size();
    return true;
  }
  static bool is_digit(char c) { return c >= '0' && c <= '9'; }
  static bool is_hex(char c) { return is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

  bool value(int depth) {
    if (depth > kMaxDepth) return false;
    switch (peek()) {
      case '{': return object(depth + 1);
      case '[': return array(depth + 1);
      case '"': return string();
      case 't': return literal("true");
      case 'f': return literal("false");
      case 'n': return literal("null");
      default: return number();
    }
  }

  bool object(int depth) {
    ++i_;  // '{'
    skip_ws();
    if (peek() == '}') {
      ++i_;
      return true;
    }
    for (;;) {
      skip_ws();
      if (peek() != '"' || !string()) return false;
      skip_ws();
      if (peek() != ':') return false;
      ++i_;
      skip_ws();
      if (!value(depth)) return false;
      skip_ws();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() == '}') {
        ++i_;
        return true;
      }
      return false;
    }
  }

  bool array(int depth) {
    ++i_;  // '['
    skip_ws();
    if (peek() == ']') {
      ++i_;
      return true;
    }
    for (;;) {
      skip_ws();
      if (!value(depth)) return false;
      skip_ws();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() == ']') {
        ++i_;
        return true;
      }
      return false;
    }
  }

  bool string() {
    const std::size_t begin = ++i_;  // past the opening quote
    while (!at_end()) {
      const auto c = static_cast<unsigned char>(t_[i_++]);
      if (c == '"') return is_valid_utf8(t_.substr(begin, i_ - 1 - begin));  // RFC 8259 section 8.1
      if (c < 0x20) return false;
      if (c == '\\') {
        if (at_end()) return false;
        const char e = t_[i_++];
        if (e == 'u') {
          for (int k = 0; k < 4; ++k)
            if (at_end() || !is_hex(t_[i_++])) return false;
        } else if (std::string_view("\"\\/bfnrt").find(e) == std::string_view::npos) {
          return false;
        }
      }
    }
    return false;
  }

  bool number() {
    if (peek() == '-') ++i_;
    if (peek() == '0') {
      ++i_;
    } else if (is_digit(peek())) {
      while (is_digit(peek())) ++i_;
    } else {
      return false;
    }
    if (peek() == '.') {
      ++i_;
      if (!is_digit(peek())) return false;
      while (is_digit(peek())) ++i_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++i_;
      if (peek() == '+' || peek() == '-') ++i_;
      if (!is_digit(peek())) return false;
      while (is_digit(peek())) ++i_;
    }
    return true;
  }

  std::string_view t_;
  std::size_t i_ = 0;
};

}  // namespace

bool json_is_valid(std::string_view text) { return JsonChecker(text).document(); }

}  // namespace fq
