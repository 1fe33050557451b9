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

TEST(JsonWriter, IllFormedUtf8BecomesTheReplacementCharacter) {
  // JSON text is UTF-8 (RFC 8259 section 8.1); a byte that is not (a Latin-1
  // record header) made summary.json unreadable to Python's json. Each
  // ill-formed sequence becomes U+FFFD (EF BF BD), one per maximal subpart
  // (the Unicode Standard, section 3.9, table 3-8's examples).
  const std::string fffd = "\xEF\xBF\xBD";
  // A stray byte: Latin-1 u-umlaut (FC) never starts a UTF-8 sequence.
  EXPECT_EQ(fq::JsonWriter::quote("D\xFCzce"), "\"D" + fffd + "zce\"");
  // A stray continuation byte.
  EXPECT_EQ(fq::JsonWriter::quote("a\x80" "b"), "\"a" + fffd + "b\"");
  // A truncated multi-byte sequence: E2 82 of the euro sign E2 82 AC, cut
  // before a letter and at the end: one U+FFFD each.
  EXPECT_EQ(fq::JsonWriter::quote("\xE2\x82x"), "\"" + fffd + "x\"");
  EXPECT_EQ(fq::JsonWriter::quote("x\xE2\x82"), "\"x" + fffd + "\"");
  // Overlong encodings: '/' as C0 AF, and as E0 80 AF (C0 is never a lead
  // byte, and after E0 a byte below A0 ends the sequence: one U+FFFD per byte).
  EXPECT_EQ(fq::JsonWriter::quote("\xC0\xAF"), "\"" + fffd + fffd + "\"");
  EXPECT_EQ(fq::JsonWriter::quote("\xE0\x80\xAF"), "\"" + fffd + fffd + fffd + "\"");
  // A UTF-16 surrogate (ED A0 80) and a code point above U+10FFFF (F4 90 80 80).
  EXPECT_EQ(fq::JsonWriter::quote("\xED\xA0\x80"), "\"" + fffd + fffd + fffd + "\"");
  EXPECT_EQ(fq::JsonWriter::quote("\xF4\x90\x80\x80"), "\"" + fffd + fffd + fffd + fffd + "\"");
  // Well-formed sequences of 2, 3 and 4 bytes pass unchanged: u-umlaut, euro sign, U+1F600.
  EXPECT_EQ(fq::JsonWriter::quote("\xC3\xBC \xE2\x82\xAC \xF0\x9F\x98\x80"),
            "\"\xC3\xBC \xE2\x82\xAC \xF0\x9F\x98\x80\"");
  // Escapes still apply around a repaired byte.
  EXPECT_EQ(fq::JsonWriter::quote("\"\xFF\n"), "\"\\\"" + fffd + "\\n\"");
  // The validator refuses strings that are not UTF-8, so raw() cannot pass them on.
  EXPECT_FALSE(fq::json_is_valid("\"D\xFCzce\""));
  EXPECT_FALSE(fq::json_is_valid("[\"\xE2\x82\"]"));
  EXPECT_FALSE(fq::json_is_valid("{\"\xC0\xAF\": 1}"));
  EXPECT_TRUE(fq::json_is_valid("\"D\xC3\xBCzce\""));
  fq::JsonWriter w;
  EXPECT_THROW(w.raw("\"D\xFCzce\""), std::invalid_argument);
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

TEST(JsonWriter, PythonReadsAStrayByteAsUtf8Json) {
  if (std::system("/usr/bin/python3 -c 'import json' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 not available for the independent check";
  fq::JsonWriter w;
  w.begin_object().key("s").value("D\xFCzce \xE2\x82").end_object();
  const std::filesystem::path file =
      std::filesystem::path(FQ_BINARY_DIR) / "test_output" / "json_writer" / "stray_byte.json";
  std::filesystem::create_directories(file.parent_path());
  { std::ofstream(file, std::ios::binary) << w.str(); }
  // Decoded strictly as UTF-8: D U+FFFD z c e space U+FFFD.
  const std::string cmd =
      "/usr/bin/python3 -c \"import json,sys; d=json.loads(open(sys.argv[1],'rb').read().decode('utf-8')); "
      "sys.exit(0 if [ord(c) for c in d['s']]==[68,0xFFFD,122,99,101,32,0xFFFD] else 1)\" '" +
      file.string() + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << w.str();
}
