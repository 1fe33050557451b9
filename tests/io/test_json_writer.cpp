// JsonWriter and json_is_valid against RFC 8259 (the JSON grammar and its
// string escapes) and, independently, against Python's json module.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "io/json_writer.h"

TEST(JsonWriter, EscapesStringsPerRfc8259) {
  // RFC 8259 section 7: quote and backslash escaped, control characters as
  // \uXXXX (or their short forms), everything else verbatim.
  EXPECT_EQ(fq::JsonWriter::quote("plain"), "\"plain\"");
  EXPECT_EQ(fq::JsonWriter::quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(fq::JsonWriter::quote("line\nnext\ttab\r"), "\"line\\nnext\\ttab\\r\"");
  EXPECT_EQ(fq::JsonWriter::quote(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
  EXPECT_EQ(fq::JsonWriter::quote("caf\xc3\xa9 / ok"), "\"caf\xc3\xa9 / ok\"");
}

TEST(JsonWriter, NumbersRoundTripAndNonFiniteIsNull) {
  // JSON has no NaN or infinity (RFC 8259 section 6).
  EXPECT_EQ(fq::JsonWriter::number(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(fq::JsonWriter::number(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(fq::JsonWriter::number(-std::numeric_limits<double>::infinity()), "null");
  // Finite values read back to the same double.
  for (double x : {0.1, 1e-5, -2.5e300, 1.0 / 3.0, 9.80665, 5e-324, 0.0, 123456789.0}) {
    const std::string s = fq::JsonWriter::number(x);
    EXPECT_TRUE(fq::json_is_valid(s)) << s;
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), x) << s;
  }
}

TEST(JsonWriter, BuildsNestedDocumentsAndRejectsMisuse) {
  fq::JsonWriter w;
  w.begin_object();
  w.key("name").value("frame \"A\"");
  w.key("steps").value(std::int64_t(100000));
  w.key("count").value(3u);
  w.key("ok").value(true);
  w.key("bad").value(std::nan(""));
  w.key("list").begin_array().value(1.5).value("x").begin_object().end_object().begin_array().end_array().end_array();
  w.key("raw").raw(" {\"a\": [1, 2]} ");
  w.key("nothing").null();
  w.end_object();
  EXPECT_TRUE(w.complete());
  EXPECT_TRUE(fq::json_is_valid(w.str())) << w.str();
  EXPECT_NE(w.str().find("\"bad\": null"), std::string::npos);
  EXPECT_NE(w.str().find("\"raw\": {\"a\": [1, 2]}"), std::string::npos);

  fq::JsonWriter compact(0);
  compact.begin_array().value(1).value(2).end_array();
  EXPECT_EQ(compact.str(), "[1,2]");

  fq::JsonWriter m1;
  m1.begin_object();
  EXPECT_THROW(m1.value(1.0), std::logic_error);  // value without a key
  EXPECT_THROW(m1.end_array(), std::logic_error);
  fq::JsonWriter m2;
  m2.begin_array();
  EXPECT_THROW(m2.key("k"), std::logic_error);
  fq::JsonWriter m3;
  EXPECT_THROW(m3.raw("{bad}"), std::invalid_argument);
  m3.value(1.0);
  EXPECT_THROW(m3.value(2.0), std::logic_error);  // two top-level values
}

TEST(JsonValidator, FollowsTheGrammar) {
  for (const char* ok : {"0", "-0.5e+10", "\"\\u00e9\\n\"", "[]", "{}", " {\"a\": [true, false, null]} ", "1E5",
                         "[1, {\"b\": \"c\"}]"})
    EXPECT_TRUE(fq::json_is_valid(ok)) << ok;
  for (const char* bad : {"", "01", "1.", ".5", "+1", "NaN", "Infinity", "[1,]", "{\"a\":1,}", "{a: 1}", "'x'",
                          "\"tab\there\"", "\"\\x\"", "[1] [2]", "tru", "{\"a\" 1}", "[", "\"open"})
    EXPECT_FALSE(fq::json_is_valid(bad)) << bad;
  std::string deep(300, '[');
  deep += std::string(300, ']');
  EXPECT_FALSE(fq::json_is_valid(deep));  // deeper than 256 levels
}

TEST(JsonWriter, PythonJsonReadsTheSameStrings) {
  if (std::system("/usr/bin/python3 -c 'import json' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 not available for the independent check";
  fq::JsonWriter w;
  w.begin_object().key("s").value(std::string("a\"b\\c\n\x01\xc3\xa9", 9)).key("x").value(0.1).end_object();
  const std::filesystem::path file =
      std::filesystem::path(FQ_BINARY_DIR) / "test_output" / "json_writer" / "strings.json";
  std::filesystem::create_directories(file.parent_path());
  { std::ofstream(file) << w.str(); }
  // Code points of a " b \ c LF U+0001 U+00E9 (RFC 8259 escapes decoded), and 0.1 exactly.
  const std::string cmd =
      "/usr/bin/python3 -c \"import json,sys; d=json.load(open(sys.argv[1])); "
      "sys.exit(0 if [ord(c) for c in d['s']]==[97,34,98,92,99,10,1,233] and d['x']==0.1 else 1)\" '" +
      file.string() + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << w.str();
}
