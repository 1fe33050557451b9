// fq::csv_text against RFC 4180, section 2: a field holding a comma, a
// double quote or a line break is enclosed in double quotes (rule 6), and a
// double quote inside it is written twice (rule 7); other fields go as they
// are. The expected texts are the RFC's rules applied by hand.
#include <gtest/gtest.h>

#include <string>

#include "io/csv_text.h"

namespace {

TEST(CsvText, PlainFieldsGoAsTheyAre) {
  EXPECT_EQ(fq::csv_text("column1_se"), "column1_se");
  EXPECT_EQ(fq::csv_text(""), "");
  EXPECT_EQ(fq::csv_text("a b;c'd"), "a b;c'd");  // spaces, semicolons, apostrophes need no quotes
}

TEST(CsvText, FieldsWithCommasQuotesOrLineBreaksAreQuoted) {
  EXPECT_EQ(fq::csv_text("out/a,b"), "\"out/a,b\"");
  EXPECT_EQ(fq::csv_text("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(fq::csv_text("\""), "\"\"\"\"");
  EXPECT_EQ(fq::csv_text("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(fq::csv_text("cr\rhere"), "\"cr\rhere\"");
}

// The tables are UTF-8: a byte that is not (a Latin-1 file name of a
// --record) becomes U+FFFD (EF BF BD) instead of making pandas' default
// reader fail on the whole file.
TEST(CsvText, IllFormedUtf8BecomesTheReplacementCharacter) {
  EXPECT_EQ(fq::csv_text("D\xFCzce"), "D\xEF\xBF\xBDzce");
  EXPECT_EQ(fq::csv_text("out/D\xFCzce,1"), "\"out/D\xEF\xBF\xBDzce,1\"");
  EXPECT_EQ(fq::csv_text("D\xC3\xBCzce"), "D\xC3\xBCzce");  // valid UTF-8 as it is
}

}  // namespace
