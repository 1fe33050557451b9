// io/utf8_text.h against the Unicode Standard's definition of well-formed
// UTF-8 (table 3-7) and ISO 8859-1, whose bytes are the code points
// U+0000..U+00FF; the expected bytes are those code points' UTF-8 forms,
// worked out by hand (U+00FC = 11 111100 -> C3 BC).
#include <gtest/gtest.h>

#include <string>

#include "io/utf8_text.h"

namespace {

TEST(Utf8Text, WellFormedAndIllFormedSequences) {
  for (const char* ok : {"", "plain ascii", "D\xC3\xBCzce", "\xE2\x82\xAC", "\xF0\x9F\x98\x80", "\xF4\x8F\xBF\xBF",
                         "\xED\x9F\xBF"})
    EXPECT_TRUE(fq::is_valid_utf8(ok)) << ok;
  for (const char* bad : {"D\xFCzce", "\x80", "\xC3", "\xE2\x82", "\xC0\xAF", "\xC1\xBF", "\xE0\x9F\xBF",
                          "\xED\xA0\x80", "\xF0\x8F\xBF\xBF", "\xF4\x90\x80\x80", "\xF5\x80\x80\x80", "\xFF"})
    EXPECT_FALSE(fq::is_valid_utf8(bad)) << bad;
}

TEST(Utf8Text, RepairReplacesEachMaximalSubpart) {
  const std::string fffd = "\xEF\xBF\xBD";
  EXPECT_EQ(fq::utf8_repaired("D\xC3\xBCzce"), "D\xC3\xBCzce");
  EXPECT_EQ(fq::utf8_repaired("D\xFCzce"), "D" + fffd + "zce");
  EXPECT_EQ(fq::utf8_repaired("\xF0\x9F\x98"), fffd);  // one truncated 4-byte sequence
  EXPECT_EQ(fq::utf8_repaired("\xC0\xAF"), fffd + fffd);
}

TEST(Utf8Text, TextThatIsNotUtf8IsReadAsLatin1) {
  // "D\xFCzce, Turkey" in Latin-1: FC = U+00FC (u-umlaut) -> C3 BC.
  EXPECT_EQ(fq::utf8_from_utf8_or_latin1("D\xFCzce, Turkey"), "D\xC3\xBCzce, Turkey");
  // A0 (no-break space) -> C2 A0, E9 (e-acute) -> C3 A9, FF (y-diaeresis) -> C3 BF.
  EXPECT_EQ(fq::utf8_from_utf8_or_latin1("\xA0\xE9\xFF"), "\xC2\xA0\xC3\xA9\xC3\xBF");
  // Valid UTF-8 is kept as it is, not read as Latin-1 a second time.
  EXPECT_EQ(fq::utf8_from_utf8_or_latin1("D\xC3\xBCzce"), "D\xC3\xBCzce");
  EXPECT_EQ(fq::utf8_from_utf8_or_latin1("ascii"), "ascii");
}

}  // namespace
