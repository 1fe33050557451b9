// A tiny streaming JSON writer (and a validator), enough for summary.json and
// for callers that format extra summary fields. No external JSON library:
// the output is small, flat and written once per run.
//
// Numbers are written in the shortest form that reads back to the same
// double (std::to_chars); JSON has no NaN or infinity, so non-finite numbers
// are written as null. Strings are escaped per RFC 8259 (quote, backslash,
// control characters); valid UTF-8 passes through unchanged, and each
// ill-formed byte sequence is written as U+FFFD, so the output is always
// UTF-8 (section 8.1). The validator refuses strings that are not UTF-8.
//
//   JsonWriter w;
//   w.begin_object().key("status").value("completed").key("dt_s").value(1e-5).end_object();
//   w.str()  ->  {\n  "status": "completed",\n  "dt_s": 1e-05\n}
// Misuse (a value where a key is due, unbalanced ends) throws std::logic_error.
#pragma once

#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace fq {

class JsonWriter {
 public:
  // indent_spaces = 0 writes everything on one line.
  explicit JsonWriter(int indent_spaces = 2);

  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(std::string_view name);

  JsonWriter& value(std::string_view s);
  JsonWriter& value(const char* s) { return value(std::string_view(s)); }
  JsonWriter& value(double x);
  JsonWriter& value(bool b);
  template <std::integral T>
    requires(!std::same_as<T, bool>)
  JsonWriter& value(T i) {
    return integer(static_cast<std::int64_t>(i));
  }
  JsonWriter& null();
  // An already formatted JSON value, inserted as is (checked with json_is_valid).
  JsonWriter& raw(std::string_view json_value);

  // The document so far; complete once every begin has its end.
  const std::string& str() const { return out_; }
  bool complete() const { return stack_.empty() && wrote_root_; }

  // "text" with quotes and escapes.
  static std::string quote(std::string_view s);
  // Shortest round-trip form of a finite x, "null" otherwise.
  static std::string number(double x);

 private:
  JsonWriter& integer(std::int64_t i);
  void before_value();
  void newline();
  struct Level {
    bool is_object;
    std::size_t count;
    bool key_pending;
  };
  std::string out_;
  std::vector<Level> stack_;
  int indent_;
  bool wrote_root_ = false;
};

// True when `text` is exactly one JSON value (RFC 8259), surrounding
// whitespace allowed, its strings UTF-8. Nesting deeper than 256 levels is
// rejected.
bool json_is_valid(std::string_view text);

}  // namespace fq
