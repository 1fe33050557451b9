// The one error type for everything a user can get wrong in an input file
// (case file, accelerogram). It always names the file, the line (1-based, 0
// when the problem is with the file as a whole), the field, and what was
// expected, so a message reads like a compiler's:
//   cases/demo.yaml:12: field 'members[3].section': expected the name of a section, got 'col10x30'
#pragma once

#include <stdexcept>
#include <string>

#include "io/utf8_text.h"

namespace fq {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string field, const std::string& message)
      : std::runtime_error(format(file, line, field, message)),
        file_(std::move(file)),
        line_(line),
        field_(std::move(field)),
        message_(message) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& field() const { return field_; }
  // What was expected, without the file, line and field (what() has them).
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& field, const std::string& message) {
    // Appended piece by piece: gcc 12 at -O3 warns falsely (-Wrestrict,
    // -Wstringop-overflow) about inlined concatenations of temporaries.
    // "file:line: ", "file: ", "line N: " (text not read from a file), or
    // nothing (a command-line option).
    std::string s = file;
    if (line > 0) {
      s += file.empty() ? "line " : ":";
      s += std::to_string(line);
    }
    if (!s.empty()) s += ": ";
    if (!field.empty()) {
      // A command-line option (--integrator) is an option, not a field.
      s += field.rfind("--", 0) == 0 ? "option '" : "field '";
      s += field;
      s += "': ";
    }
    s += message;
    // The message quotes the user's text, which may not be UTF-8 (a case
    // name typed in Latin-1 reached the terminal as a raw byte; review
    // probe): ill-formed bytes are shown as U+FFFD.
    return utf8_repaired(s);
  }
  std::string file_;
  int line_;
  std::string field_;
  std::string message_;
};

}  // namespace fq
