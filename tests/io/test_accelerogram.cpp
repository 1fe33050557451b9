// Accelerogram readers (io/accelerogram.h): the eight PEER records shipped in
// ../shared/data/ground_motions, line-end independence, every malformed-input
// error, and the two-column reader's uniform / non-uniform / unit paths.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dem_core/ground_motion.h"
#include "io/accelerogram.h"
#include "io/input_error.h"
#include "io/utf8_text.h"

namespace fs = std::filesystem;

namespace {

const fs::path kGroundMotions = fs::path(FQ_SHARED_DIR) / "data" / "ground_motions";

// A fresh directory under the system temp dir, removed with its contents.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = fs::temp_directory_path() /
            ("fq_test_accelerogram_" + std::to_string(stamp) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path p = path_ / name;
    std::ofstream out(p, std::ios::binary);
    out << bytes;
    return p;
  }

 private:
  fs::path path_;
};

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// LF -> `eol` (input must contain no CR).
std::string with_line_ends(const std::string& lf_text, const std::string& eol) {
  std::string out;
  out.reserve(lf_text.size() * 2);
  for (const char c : lf_text) {
    if (c == '\n')
      out += eol;
    else
      out += c;
  }
  return out;
}

// CRLF -> LF.
std::string strip_cr(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text)
    if (c != '\r') out += c;
  return out;
}

constexpr double kG = 9.80665;  // standard gravity (m/s^2), PEER's g

}  // namespace

// ---- the shipped PEER records --------------------------------------------------

// Expected values are the columns N, DT, PGA (g) and "t at peak" of the table in
// ../shared/data/ground_motions/README.md. Its NPTS/DT were read from each header
// and the count of values checked by an independent Python script; the records
// were matched against PEER's own velocity files and NGA-West2 response spectra
// (README "Extra checks"). Peak = signed sample of largest magnitude, at i*DT.
struct ShippedRecord {
  long npts;
  double dt_s;
  double pga_g;
  double t_peak_s;
};

const std::map<std::string, ShippedRecord>& readme_table() {
  static const std::map<std::string, ShippedRecord> table = {
      {"RSN1106_KOBE_KJM000.AT2", {7500, 0.02, -0.8342289, 8.52}},
      {"RSN1106_KOBE_KJM090.AT2", {7500, 0.02, +0.6296560, 8.44}},
      {"RSN1106_KOBE_KJM-UP.AT2", {7500, 0.02, +0.3389118, 7.72}},
      {"RSN6_IMPVALL.I_I-ELC180.AT2", {5372, 0.01, -0.2807955, 2.18}},
      {"RSN1044_NORTHR_NWH360.AT2", {2000, 0.02, +0.5904105, 4.32}},
      {"RSN1044_NORTHR_NWH090.AT2", {2000, 0.02, -0.5829885, 5.34}},
      {"TAK000.AT2", {4096, 0.01, +0.6177107, 5.82}},
      {"RSN1120_KOBE_TAK090.AT2", {4096, 0.01, +0.6710559, 2.82}},
  };
  return table;
}

TEST(PeerAt2, EveryShippedRecordMatchesTheReadmeTable) {
  int seen = 0;
  for (const auto& entry : fs::directory_iterator(kGroundMotions)) {
    if (entry.path().extension() != ".AT2") continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const auto it = readme_table().find(name);
    ASSERT_NE(it, readme_table().end()) << "file not in the README table";
    const ShippedRecord& ref = it->second;
    const fq::AccelerationRecord rec = fq::read_peer_at2(entry.path());
    ++seen;
    EXPECT_EQ(rec.source, entry.path().string());
    EXPECT_EQ(long(rec.acceleration_mps2.size()), ref.npts);
    // DT is printed with 3-4 decimals in the header; parsing must give the
    // nearest double to the decimal value.
    EXPECT_DOUBLE_EQ(rec.dt_s, ref.dt_s);
    // The file stores 7 significant digits in g; the README quotes them as
    // stored, so only the round trip through m/s^2 separates the two.
    double t_peak_s = -1.0;
    const double peak_mps2 = rec.peak_mps2(&t_peak_s);
    EXPECT_NEAR(peak_mps2 / kG, ref.pga_g, 1e-12);
    EXPECT_NEAR(t_peak_s, ref.t_peak_s, 1e-9);
  }
  EXPECT_EQ(seen, int(readme_table().size())) << "every README record must be present";
}

TEST(PeerAt2, DescriptionIsHeaderLineTwo) {
  // Header line 2 as quoted in the README (provenance of KJM000 and TAK000;
  // TAK000's line carries trailing blanks and CRLF, which are not text).
  EXPECT_EQ(fq::read_peer_at2(kGroundMotions / "RSN1106_KOBE_KJM000.AT2").description,
            "Kobe Japan, 1/16/1995, KJMA, 0");
  EXPECT_EQ(fq::read_peer_at2(kGroundMotions / "TAK000.AT2").description, "KOBE, 01/16/1995, Takatori, 000");
}

TEST(PeerAt2, JmaKobePeaksMatchPublishedValues) {
  // Published JMA Kobe peaks: 818 gal NS, 617 gal EW, 332 gal UD (JMA; PEER
  // NGA-West2 RSN1106, README "Match with published values"; seed 000 quotes
  // 8.2 / 6.0 / 3.3 m/s^2). Times are those of the PEER time axis (README),
  // which starts about 3.0 s before the seed's (5.5 / 5.5 / 4.7 s).
  struct Case {
    const char* file;
    double peak_cmps2;
    double t_s;
  };
  const Case cases[] = {
      {"RSN1106_KOBE_KJM000.AT2", -818.1, 8.52},
      {"RSN1106_KOBE_KJM090.AT2", +617.5, 8.44},
      {"RSN1106_KOBE_KJM-UP.AT2", +332.4, 7.72},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const fq::AccelerationRecord rec = fq::read_peer_at2(kGroundMotions / c.file);
    double t_s = -1.0;
    const double peak_cmps2 = rec.peak_mps2(&t_s) * 100.0;
    EXPECT_NEAR(peak_cmps2, c.peak_cmps2, 0.5);  // published to 0.1 cm/s^2
    EXPECT_NEAR(t_s, c.t_s, 1e-9);               // i * DT exactly
  }
}

// ---- line ends -----------------------------------------------------------------

const std::string kSynthHead =
    "PEER NGA STRONG MOTION DATABASE RECORD\n"
    "Synthetic, 1/1/2000, Nowhere, 0\n"
    "ACCELERATION TIME SERIES IN UNITS OF G\n";

void expect_same_record(const fq::AccelerationRecord& a, const fq::AccelerationRecord& b) {
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.dt_s, b.dt_s);
  EXPECT_EQ(a.acceleration_mps2, b.acceleration_mps2);  // bitwise: the same tokens are parsed
}

TEST(PeerAt2, CrlfAndLfGiveIdenticalRecords) {
  // The same data must parse identically whatever the line ends: LF file ->
  // CRLF and CR-only copies; CRLF file -> LF copy.
  TempDir dir;
  const std::string lf = read_bytes(kGroundMotions / "RSN1106_KOBE_KJM000.AT2");
  ASSERT_EQ(lf.find('\r'), std::string::npos) << "README says KJM000 is LF";
  const fq::AccelerationRecord from_lf = fq::read_peer_at2(kGroundMotions / "RSN1106_KOBE_KJM000.AT2");
  expect_same_record(from_lf, fq::read_peer_at2(dir.write("kjm000_crlf.AT2", with_line_ends(lf, "\r\n"))));
  expect_same_record(from_lf, fq::read_peer_at2(dir.write("kjm000_cr.AT2", with_line_ends(lf, "\r"))));
  EXPECT_EQ(from_lf.acceleration_mps2.size(), 7500u);

  const std::string crlf = read_bytes(kGroundMotions / "RSN1044_NORTHR_NWH360.AT2");
  ASSERT_NE(crlf.find("\r\n"), std::string::npos) << "README says NWH360 is CRLF";
  expect_same_record(fq::read_peer_at2(kGroundMotions / "RSN1044_NORTHR_NWH360.AT2"),
                     fq::read_peer_at2(dir.write("nwh360_lf.AT2", strip_cr(crlf))));
}

// A record that is a pipe is refused at once, not opened: opening a FIFO
// blocks until a writer comes, which Ctrl-C cannot stop (a CLI probe's
// `sweep --record` on a FIFO hung until SIGKILL).
TEST(PeerAt2, APipeIsRefusedNotOpened) {
  TempDir dir;
  const fs::path fifo = dir.path() / "record.AT2";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    (void)fq::read_peer_at2(fifo);
    ADD_FAILURE() << "accepted a pipe";
  } catch (const fq::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fifo.string()), std::string::npos) << e.what();
  }
}

TEST(TwoColumn, CrlfAndLfGiveIdenticalRecords) {
  TempDir dir;
  const std::string lf = "# crlf check\n0.0 1.0\n0.01 -2.0\n0.02 0.5\n";
  expect_same_record(fq::read_two_column(dir.write("lf.txt", lf), fq::AccelerationUnit::MetrePerSecond2),
                     fq::read_two_column(dir.write("crlf.txt", with_line_ends(lf, "\r\n")),
                                         fq::AccelerationUnit::MetrePerSecond2));
}

// ---- number syntax -------------------------------------------------------------

TEST(PeerAt2, ReadsFortranEAndDExponentsAndTolerantLineFour) {
  // Values chosen so each token's meaning is known by hand (in g).
  TempDir dir;
  const std::string text =
      "PEER NGA STRONG MOTION DATABASE RECORD\n"
      "Synthetic, 1/1/2000, Nowhere, 0\n"
      "ACCELERATION TIME SERIES IN UNITS OF G\n"
      "npts =5 dt=.0050SEC\n"  // lower case, no comma, unit glued to the number
      "  -.1416764E-03   .15D+01  +2.5  -1.25d-1\n"
      "  4\n";
  const fq::AccelerationRecord rec = fq::read_peer_at2(dir.write("syn.AT2", text));
  ASSERT_EQ(rec.acceleration_mps2.size(), 5u);
  EXPECT_DOUBLE_EQ(rec.dt_s, 0.005);
  const double expected_g[] = {-0.1416764e-3, 1.5, 2.5, -0.125, 4.0};
  for (std::size_t k = 0; k < 5; ++k) EXPECT_DOUBLE_EQ(rec.acceleration_mps2[k], expected_g[k] * kG) << k;
}

// Subnormal values (below 2.2e-308, down to about 4.9e-324) are read as
// they are, as the case file's numbers are; only a value that rounds to 0
// is refused (bad_inputs: at2_value_underflows, two_accel_underflows).
TEST(PeerAt2, ReadsSubnormalValuesAsTheyAre) {
  TempDir dir;
  const fq::AccelerationRecord rec = fq::read_peer_at2(
      dir.write("subnormal.AT2", kSynthHead + "NPTS= 3, DT= .0100 SEC\n  1E-310  -5D-324  .25E-307\n"));
  ASSERT_EQ(rec.acceleration_mps2.size(), 3u);
  EXPECT_DOUBLE_EQ(rec.acceleration_mps2[0], 1e-310 * kG);
  EXPECT_DOUBLE_EQ(rec.acceleration_mps2[1], -5e-324 * kG);
  EXPECT_DOUBLE_EQ(rec.acceleration_mps2[2], 0.25e-307 * kG);
}

// Line 4 in the layout of older PEER files (numbers first, then their
// names), with the NGA keywords in reverse order, and as two bare numbers
// (records probe: each was refused). NPTS and DT are those written in each
// file; the values are the same five in g.
TEST(PeerAt2, ReadsTheOlderAndReversedLineFourLayouts) {
  TempDir dir;
  const std::string head =
      "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n"
      "IMPERIAL VALLEY 05/19/40 0439, EL CENTRO ARRAY #9, 180\n"
      "ACCELERATION TIME SERIES IN UNITS OF G\n";
  const std::string values = "   .1000000E-02   .2000000E-02  -.3000000E-02   .4000000E-02   .5000000E-02\n";
  struct Layout {
    const char* label;
    const char* line4;
    double dt_s;
  };
  const Layout layouts[] = {
      {"labelled", "  5    0.0100    NPTS, DT", 0.01},
      {"labelled_lower_no_comma", "5 .005 npts dt", 0.005},
      {"labelled_dt_first", "  0.0200    5    DT, NPTS", 0.02},
      {"reversed_keywords", "DT= 0.0100 SEC, NPTS= 5", 0.01},
      {"reversed_keywords_spaced", "dt = .0050 sec , npts = 5 ,", 0.005},
      {"bare", "5 0.0100", 0.01},
      {"bare_exponent", "   5   1.0E-02", 0.01},
      // A '+' sign on NPTS (std::from_chars reads none; review probe).
      {"bare_plus_sign", "+5 0.0100", 0.01},
      {"keywords_plus_sign", "NPTS= +5, DT= .0100 SEC", 0.01},
  };
  const double expected_g[] = {0.001, 0.002, -0.003, 0.004, 0.005};
  for (const Layout& l : layouts) {
    SCOPED_TRACE(l.label);
    const fq::AccelerationRecord rec =
        fq::read_peer_at2(dir.write(std::string(l.label) + ".AT2", head + l.line4 + "\n" + values));
    EXPECT_DOUBLE_EQ(rec.dt_s, l.dt_s);
    ASSERT_EQ(rec.acceleration_mps2.size(), 5u);
    for (std::size_t k = 0; k < 5; ++k) EXPECT_DOUBLE_EQ(rec.acceleration_mps2[k], expected_g[k] * kG) << k;
    EXPECT_EQ(rec.description, "IMPERIAL VALLEY 05/19/40 0439, EL CENTRO ARRAY #9, 180");
  }
  // The spellings of seconds real files use, glued or not, in any case,
  // with brackets or a trailing '.', or no unit (review probe: any other
  // unit was ignored; those are refused in bad_inputs, at2_dt_in_*).
  for (const char* line4 : {"NPTS= 5, DT= .0100 SEC", "NPTS= 5, DT= .0100 SECS,", "NPTS= 5, DT= .0100 S",
                            "NPTS= 5, DT= .0100 seconds", "NPTS= 5, DT= .0100 Sec.", "NPTS= 5, DT= .0100 (s)",
                            "NPTS= 5, DT= .0100", "NPTS= 5, DT= .0100,", "DT= .0100 NPTS= 5", "NPTS= 5, DT= .0100s",
                            "NPTS= 5, DT= 1.0E-02SECS", "5 .0100S", "  5    0.0100sec    NPTS, DT"}) {
    SCOPED_TRACE(line4);
    const fq::AccelerationRecord rec = fq::read_peer_at2(dir.write("seconds.AT2", head + line4 + "\n" + values));
    EXPECT_DOUBLE_EQ(rec.dt_s, 0.01);
    EXPECT_EQ(rec.acceleration_mps2.size(), 5u);
  }
  // NPTS is checked against the values in every layout.
  try {
    (void)fq::read_peer_at2(dir.write("labelled_short.AT2", head + "  6    0.0100    NPTS, DT\n" + values));
    ADD_FAILURE() << "accepted 5 values for NPTS 6";
  } catch (const fq::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("declares NPTS=6 but the file holds 5 values"), std::string::npos)
        << e.what();
  }
}

// Old DOS-written files end with Ctrl-Z (0x1A); as the last byte(s) it is
// not content (records probe: refused as a non-text byte). Elsewhere it
// still is binary (bad_inputs: at2_eof_mark_inside, two_eof_mark_inside).
TEST(Accelerogram, ATrailingDosEndOfFileMarkIsIgnored) {
  TempDir dir;
  const std::string at2 = kSynthHead + "NPTS= 3, DT= .0100 SEC\n  .1E-02  -.2E-02  .3E-02";
  const fq::AccelerationRecord plain = fq::read_peer_at2(dir.write("plain.AT2", at2 + "\n"));
  ASSERT_EQ(plain.acceleration_mps2.size(), 3u);
  EXPECT_DOUBLE_EQ(plain.acceleration_mps2[1], -0.002 * kG);
  for (const std::string& tail : {std::string("\n\x1a"), std::string("\x1a"), std::string("\r\n\x1a\x1a")}) {
    SCOPED_TRACE(tail.size());
    expect_same_record(plain, fq::read_peer_at2(dir.write("eof.AT2", at2 + tail)));
  }
  const std::string two = "# dos file\n0.00 1.5\n0.01 -2.5\n";
  const fq::AccelerationRecord two_plain = fq::read_two_column(dir.write("plain.txt", two), fq::AccelerationUnit::G);
  const fq::AccelerationRecord two_eof =
      fq::read_two_column(dir.write("eof.txt", two + "\x1a"), fq::AccelerationUnit::G);
  expect_same_record(two_plain, two_eof);
  EXPECT_EQ(two_eof.acceleration_mps2, (std::vector<double>{1.5 * kG, -2.5 * kG}));
  // A file of nothing but the mark is empty.
  EXPECT_THROW((void)fq::read_peer_at2(dir.write("only.AT2", "\x1a")), fq::InputError);
}

// Line 3 without "UNITS OF" is read for what it names (bad_inputs: another
// quantity or unit is refused), but a line that names acceleration, a
// date's slashes, words with a slash that are no unit ("N/S", "CDMG/USGS";
// review, stop 41) or nothing of these is not refused: the shipped
// records' form, an older one, and lines written by hand.
TEST(PeerAt2, ALineThreeNamingAccelerationOrNoUnitIsRead) {
  TempDir dir;
  const std::string rest = "NPTS= 2, DT= .0100 SEC\n  .1E-02  .2E-02\n";
  for (const char* line3 : {"ACCELERATION TIME HISTORY IN UNITS OF G", "Acceleration, velocity and displacement",
                            "processed 10/15/79 (g)", "horizontal component", "", "ACCELERATION, COMPONENT N/S",
                            "Recorded by CDMG/USGS"}) {
    SCOPED_TRACE(line3);
    const fq::AccelerationRecord r =
        fq::read_peer_at2(dir.write("line3.AT2", "PEER NGA STRONG MOTION DATABASE RECORD\nx\n" +
                                                     std::string(line3) + "\n" + rest));
    EXPECT_EQ(r.acceleration_mps2.size(), 2u);
  }
}

// Header text that is not UTF-8 is Latin-1 (older and Windows-written
// files): "D\xFCzce" is kept as "Düzce" in UTF-8 (FC = U+00FC -> C3 BC), so
// that summary.json and the warnings that quote it are UTF-8 (records
// probe: the raw byte made summary.json unreadable to Python). UTF-8 text
// is kept as it is.
TEST(PeerAt2, Latin1HeaderTextIsReadAsLatin1) {
  TempDir dir;
  const std::string rest = "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 2, DT= .0100 SEC\n  .1E-02  .2E-02\n";
  EXPECT_EQ(fq::read_peer_at2(dir.write("latin1.AT2", "PEER NGA STRONG MOTION DATABASE RECORD\n"
                                                      "D\xFCzce, Turkey, 11/12/1999, D\xFCzce, UP\n" + rest))
                .description,
            "D\xC3\xBCzce, Turkey, 11/12/1999, D\xC3\xBCzce, UP");
  EXPECT_EQ(fq::read_peer_at2(dir.write("utf8.AT2", "PEER NGA STRONG MOTION DATABASE RECORD\n"
                                                    "D\xC3\xBCzce, Turkey, 11/12/1999, D\xC3\xBCzce, UP\n" + rest))
                .description,
            "D\xC3\xBCzce, Turkey, 11/12/1999, D\xC3\xBCzce, UP");
  // A two-column file's first comment is kept the same way.
  const fq::AccelerationRecord two =
      fq::read_two_column(dir.write("latin1.txt", "# D\xFCzce station\n0.00 1\n0.01 2\n"), fq::AccelerationUnit::G);
  EXPECT_EQ(two.description.rfind("D\xC3\xBCzce station [", 0), 0u) << two.description;
  // Messages quote the file's text as UTF-8 too, and never cut a character
  // in two when they shorten it (60 bytes are shown).
  const std::string long_token = std::string(59, '7') + "\xC3\xBC" + "0";
  for (const std::string& token : {std::string("1.0\xB0"), long_token}) {
    try {
      (void)fq::read_peer_at2(dir.write("bad_token.AT2", kSynthHead + "NPTS= 2, DT= .0100 SEC\n  " + token + " 1\n"));
      ADD_FAILURE() << "accepted " << token;
    } catch (const fq::InputError& e) {
      EXPECT_TRUE(fq::is_valid_utf8(e.what())) << e.what();
      if (token.size() < 10) {
        EXPECT_NE(std::string(e.what()).find("'1.0\xC2\xB0'"), std::string::npos) << e.what();
      }
    }
  }
}

// ---- malformed input -----------------------------------------------------------

struct BadInput {
  const char* label;
  fq::RecordFormat format;
  std::string content;  // written to <label>.txt; "<missing>" means no file
  int line;             // expected 1-based line (0: file as a whole)
  const char* field;
  const char* also;  // further text the message must contain ("" for none)
};

const std::string kHead =
    "PEER NGA STRONG MOTION DATABASE RECORD\n"
    "Synthetic, 1/1/2000, Nowhere, 0\n"
    "ACCELERATION TIME SERIES IN UNITS OF G\n";

std::vector<BadInput> bad_inputs() {
  using F = fq::RecordFormat;
  const std::string five = "  .1E-02  .2E-02  .3E-02  .4E-02  .5E-02\n";
  return {
      {"at2_missing", F::PeerAt2, "<missing>", 0, "file", "not found"},
      {"at2_empty", F::PeerAt2, "", 0, "file", "empty"},
      {"at2_binary_header", F::PeerAt2, std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), 2, "header", "0x1A"},
      {"at2_binary_data", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n" + five + std::string("\0\x01\x02", 3), 6,
       "value", "0x00"},
      {"at2_three_header_lines", F::PeerAt2, kHead, 4, "header", "4 header lines"},
      {"at2_no_npts", F::PeerAt2, kHead + "DT= .0100 SEC\n" + five, 4, "NPTS", "NPTS="},
      {"at2_no_npts_layouts", F::PeerAt2, kHead + "DT= .0100 SEC\n" + five, 4, "NPTS", "the layouts read are"},
      {"at2_no_dt", F::PeerAt2, kHead + "NPTS= 5,\n" + five, 4, "DT", "DT="},
      {"at2_npts_zero", F::PeerAt2, kHead + "NPTS= 0, DT= .01 SEC\n", 4, "NPTS", "positive"},
      {"at2_npts_negative", F::PeerAt2, kHead + "NPTS= -5, DT= .01 SEC\n" + five, 4, "NPTS", "'-5'"},
      {"at2_npts_not_integer", F::PeerAt2, kHead + "NPTS= 5.5, DT= .01 SEC\n" + five, 4, "NPTS", "'5.5'"},
      // A download cut inside its last value that still holds NPTS values
      // (records probe: "-.1790158E-0" for E-02, read 100 times too large).
      {"at2_last_value_cut", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  .2E-02  .3E-02  .4E-02  .5E-0\n", 5,
       "value", "'.5E-0'"},
      {"at2_one_sample", F::PeerAt2, kHead + "NPTS= 1, DT= .01 SEC\n  .1E-02\n", 4, "NPTS", "at least 2"},
      {"at2_dt_zero", F::PeerAt2, kHead + "NPTS= 5, DT= .0000 SEC\n" + five, 4, "DT", "positive"},
      {"at2_dt_negative", F::PeerAt2, kHead + "NPTS= 5, DT= -.01 SEC\n" + five, 4, "DT", "'-.01'"},
      {"at2_dt_nan", F::PeerAt2, kHead + "NPTS= 5, DT= nan SEC\n" + five, 4, "DT", "'nan'"},
      {"at2_dt_inf", F::PeerAt2, kHead + "NPTS= 5, DT= inf SEC\n" + five, 4, "DT", "'inf'"},
      {"at2_dt_text", F::PeerAt2, kHead + "NPTS= 5, DT= fast SEC\n" + five, 4, "DT", "'fast'"},
      {"at2_velocity_units", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nVELOCITY TIME SERIES IN UNITS OF CM/S\nNPTS= 5, DT= .01 SEC\n" +
           five,
       3, "header", "'CM/S'"},
      {"at2_token", F::PeerAt2, kHead + "NPTS= 10, DT= .01 SEC\n" + five + "  .1E-02  .2E-0x  .3E-02\n", 6, "value",
       "'.2E-0x'"},
      {"at2_nan_value", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  NaN  .3E-02  .4E-02  .5E-02\n", 5,
       "value", "'NaN'"},
      {"at2_inf_value", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  -inf  .3E-02  .4E-02  .5E-02\n", 5,
       "value", "'-inf'"},
      {"at2_overflow_value", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  .1E+999  .3E-02  .4E-02  .5E-02\n",
       5, "value", "'.1E+999'"},
      // A value that rounds to 0 (review probe: called "not finite");
      // subnormals are read (SubnormalValuesAreRead).
      {"at2_value_underflows", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  1e-400  .3E-02  .4E-02  .5E-02\n",
       5, "value",
       "expected a number (value 2 of NPTS=5, in g), got '1e-400', which is too small in magnitude to represent "
       "(below about 4.9e-324"},
      {"at2_value_underflows_fortran", F::PeerAt2,
       kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  .2E-02  .3E-02  .4E-02\n  -.1D-999\n", 6, "value",
       "'-.1D-999', which is too small in magnitude"},
      {"at2_value_underflows_long_exponent", F::PeerAt2,
       kHead + "NPTS= 5, DT= .01 SEC\n  1e-99999999999999999999  .2E-02  .3E-02  .4E-02  .5E-02\n", 5, "value",
       "too small in magnitude"},
      {"at2_value_overflows_below_one_exponent", F::PeerAt2,
       kHead + "NPTS= 5, DT= .01 SEC\n  1" + std::string(400, '0') + "e-50  .2E-02  .3E-02  .4E-02  .5E-02\n", 5,
       "value", "expected a finite number"},
      // 8 values over lines 5-6, the file ends at line 7 (blank).
      {"at2_too_few", F::PeerAt2, kHead + "NPTS= 10, DT= .01 SEC\n" + five + "  .1E-02  .2E-02  .3E-02\n\n", 7,
       "NPTS", "holds 8 values; expected 10"},
      // Values 6 and 7 are surplus; the first sits on line 6.
      {"at2_too_many", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n" + five + "  .6E-02  .7E-02\n", 6, "NPTS",
       "holds 7 values; expected 5"},
      {"at2_header_only", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n", 4, "NPTS", "holds 0 values"},
      // Values no ground motion has (the bounds and their sources are in
      // accelerogram.cpp): 1e300 g once ran to the end with infinite
      // displacements; 25 g is above the 20 g bound, five times the
      // largest acceleration ever recorded.
      {"at2_absurd_value", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  .1E+301  .3E-02  .4E-02  .5E-02\n",
       5, "value", "expected at most 20 g"},
      {"at2_value_above_20_g", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02  .2E-02  .3E-02  .4E-02\n -.25E+02\n",
       6, "value", "got -25 g"},
      {"at2_dt_far_too_small", F::PeerAt2, kHead + "NPTS= 5, DT= 1E-300 SEC\n" + five, 4, "DT",
       "expected a sampling interval"},
      {"at2_dt_far_too_large", F::PeerAt2, kHead + "NPTS= 5, DT= 10.0 SEC\n" + five, 4, "DT", "got 10 s"},
      // A time unit other than seconds (review probe: ignored, so DT= .5
      // MSEC was read as 0.5 s and DT= .01 MIN as 0.01 s), glued or not.
      {"at2_dt_in_msec", F::PeerAt2, kHead + "NPTS= 5, DT= .5 MSEC\n" + five, 4, "DT",
       "expected the time step in seconds (unit SEC, SECS, S, SECONDS or none) on header line 4, got unit 'MSEC'"},
      {"at2_dt_in_min", F::PeerAt2, kHead + "NPTS= 5, DT= .01 MIN,\n" + five, 4, "DT", "got unit 'MIN'"},
      {"at2_dt_in_ms_glued", F::PeerAt2, kHead + "npts= 5 dt= 10ms\n" + five, 4, "DT", "got unit 'ms'"},
      {"at2_dt_in_microseconds", F::PeerAt2, kHead + "NPTS= 5, DT= 500 \xC2\xB5s\n" + five, 4, "DT",
       "got unit '\xC2\xB5s'"},
      {"at2_reversed_dt_in_msec", F::PeerAt2, kHead + "DT= 10 MSEC, NPTS= 5\n" + five, 4, "DT", "got unit 'MSEC'"},
      {"at2_labelled_dt_in_ms", F::PeerAt2, kHead + "  5    10MS    NPTS, DT\n" + five, 4, "DT", "got unit 'MS'"},
      // A key given twice (review probe: the second value was ignored).
      {"at2_npts_twice", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC, NPTS= 7\n" + five, 4, "NPTS",
       "expected NPTS= once on header line 4, got it twice"},
      {"at2_dt_twice", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC, DT= .02 SEC\n" + five, 4, "DT",
       "expected DT= once on header line 4, got it twice"},
      {"at2_reversed_dt_twice", F::PeerAt2, kHead + "dt= .01 sec npts= 5 dt =.01 sec\n" + five, 4, "DT", "twice"},
      // A second number after a key's value (input probe, stop 41: "DT= .02
      // .01 SEC" played the record at .02 s, half speed).
      {"at2_dt_two_values", F::PeerAt2, kHead + "NPTS= 5, DT= .02 .01 SEC\n" + five, 4, "DT",
       "expected one value after DT=, got '.02 .01' in"},
      {"at2_npts_two_values", F::PeerAt2, kHead + "NPTS= 5 7, DT= .01 SEC\n" + five, 4, "NPTS",
       "expected one value after NPTS=, got '5 7'"},
      // Line 3 naming another quantity or unit without "UNITS OF" (same
      // probe: both read as acceleration in g).
      {"at2_velocity_no_units_of", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nVELOCITY TIME SERIES\nNPTS= 5, DT= .01 SEC\n" + five, 3,
       "header", "got a line naming 'VELOCITY'"},
      {"at2_displacement_no_units_of", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nDisplacement time history (cm)\nNPTS= 5, DT= .01 SEC\n" + five,
       3, "header", "'Displacement'"},
      {"at2_cms2_no_units_of", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nACCELERATION IN CM/S/S\nNPTS= 5, DT= .01 SEC\n" + five, 3,
       "header", "got unit 'CM/S/S'"},
      {"at2_ms2_no_units_of", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nAcceleration [m/s^2]\nNPTS= 5, DT= .01 SEC\n" + five, 3,
       "header", "got unit 'm/s^2'"},
      {"at2_gal_no_units_of", F::PeerAt2,
       "PEER NGA STRONG MOTION DATABASE RECORD\nx\nACCELERATION (GAL)\nNPTS= 5, DT= .01 SEC\n" + five, 3,
       "header", "got unit 'GAL'"},
      // The other layouts of line 4 (older PEER files, keywords reversed,
      // two bare numbers) get the same checks and messages on their values.
      {"at2_labelled_npts_negative", F::PeerAt2, kHead + "  -5    .0100    NPTS, DT\n" + five, 4, "NPTS", "'-5'"},
      {"at2_labelled_npts_not_integer", F::PeerAt2, kHead + "  5.5    .0100    NPTS, DT\n" + five, 4, "NPTS",
       "'5.5'"},
      {"at2_labelled_dt_zero", F::PeerAt2, kHead + "  5    0.0000    NPTS, DT\n" + five, 4, "DT", "positive"},
      {"at2_labelled_dt_nan", F::PeerAt2, kHead + "  5    nan    NPTS, DT\n" + five, 4, "DT", "'nan'"},
      {"at2_labelled_dt_too_large", F::PeerAt2, kHead + "  5    10.0    NPTS, DT\n" + five, 4, "DT", "got 10 s"},
      {"at2_reversed_npts_zero", F::PeerAt2, kHead + "DT= .0100 SEC, NPTS= 0\n", 4, "NPTS", "positive"},
      {"at2_reversed_dt_negative", F::PeerAt2, kHead + "DT= -.01 SEC, NPTS= 5\n" + five, 4, "DT", "'-.01'"},
      {"at2_bare_one_sample", F::PeerAt2, kHead + "1 .0100\n  .1E-02\n", 4, "NPTS", "at least 2"},
      {"at2_bare_npts_negative", F::PeerAt2, kHead + "-5 .0100\n" + five, 4, "NPTS", "'-5'"},
      {"at2_npts_beyond_long_long", F::PeerAt2, kHead + "NPTS= 99999999999999999999, DT= .01 SEC\n" + five, 4, "NPTS",
       "expected a number of samples a record can hold"},
      {"at2_bare_dt_zero", F::PeerAt2, kHead + "5 0.0\n" + five, 4, "DT", "positive"},
      // Lines 4 in none of the layouts, or bare numbers that could be read
      // either way round, are refused with the layouts listed.
      {"at2_bare_two_whole_numbers", F::PeerAt2, kHead + "5 1\n" + five, 4, "NPTS", "the layouts read are"},
      {"at2_bare_dt_first", F::PeerAt2, kHead + ".0100 5\n" + five, 4, "NPTS", "the layouts read are"},
      {"at2_one_label", F::PeerAt2, kHead + "5 .0100 NPTS\n" + five, 4, "NPTS", "'5372  .0100  NPTS, DT'"},
      {"at2_labels_first", F::PeerAt2, kHead + "NPTS, DT 5 .0100\n" + five, 4, "NPTS", "older PEER files"},
      {"at2_three_numbers", F::PeerAt2, kHead + "5 .0100 7\n" + five, 4, "NPTS", "the layouts read are"},
      // A DOS end-of-file mark is read only as the file's last byte(s):
      // inside the data, or followed by a line end, it is binary.
      {"at2_eof_mark_inside", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n  .1E-02\x1a  .2E-02  .3E-02  .4E-02  .5E-02\n",
       5, "value", "0x1A"},
      {"at2_eof_mark_then_line_end", F::PeerAt2, kHead + "NPTS= 5, DT= .01 SEC\n" + five + "\x1a\n", 6, "value",
       "0x1A"},

      {"two_missing", F::TwoColumn, "<missing>", 0, "file", "not found"},
      {"two_empty", F::TwoColumn, "", 0, "file", "empty"},
      {"two_binary", F::TwoColumn, std::string("0.0 1.0\n\x7f\x45LF\x02\x01\x01\0", 16), 2, "value", "0x7F"},
      {"two_comments_only", F::TwoColumn, "# nothing here\n\n# still nothing\n", 3, "value", "found 0"},
      {"two_one_sample", F::TwoColumn, "# one row\n0.0 1.0\n", 2, "value", "found 1"},
      // More columns than two, with the likely reason (input probe, stop
      // 41): decimal commas with semicolons, a header line not commented
      // out; three plain numbers get no guess.
      {"two_decimal_commas", F::TwoColumn, "0,00;0,009792\n0,01;0,0101\n", 1, "value",
       "found 3: '0,00;0,009792' (numbers with decimal commas? write them with a point"},
      {"two_quoted_header", F::TwoColumn, "\"time (s)\",\"acc\",\"vel\"\n0 1\n0.01 2\n", 1, "value",
       "found 4: '\"time (s)\",\"acc\",\"vel\"' (a header line? start it with '#')"},
      {"two_three_numbers", F::TwoColumn, "0 1.0 2.5E-01\n0.01 2 3\n", 1, "value", "found 3: '0 1.0 2.5E-01'"},
      {"two_blank_decimal_commas", F::TwoColumn, "0,00 0,009792\n", 1, "value", "(numbers with decimal commas?"},
      {"two_time_decreasing", F::TwoColumn, "0.00 1\n0.02 2\n0.01 3\n", 3, "time", "increase"},
      {"two_time_repeated", F::TwoColumn, "0.00 1\n0.01 2\n0.01 3\n", 3, "time", "line 2"},
      {"two_time_text", F::TwoColumn, "0.00 1\nt 2\n", 2, "time", "'t'"},
      {"two_time_inf", F::TwoColumn, "0.00 1\ninf 2\n", 2, "time", "'inf'"},
      {"two_accel_text", F::TwoColumn, "0.00 1\n0.01 2g\n", 2, "acceleration", "'2g'"},
      {"two_accel_nan", F::TwoColumn, "0.00 1\n\n0.01 nan\n", 3, "acceleration", "'nan'"},
      {"two_accel_underflows", F::TwoColumn, "0.00 1\n0.01 -2.5e-400\n", 2, "acceleration",
       "expected an acceleration in m/s2, got '-2.5e-400', which is too small in magnitude to represent"},
      {"two_three_columns", F::TwoColumn, "0.00 1\n0.01 2 3\n", 2, "value", "found 3"},
      {"two_one_column", F::TwoColumn, "0.00 1\n0.01\n", 2, "acceleration", "found 1"},
      {"two_empty_field", F::TwoColumn, "0.00, 1\n0.01,,2\n", 2, "value", "empty field"},
      // 0.0200010 is a typo for 0.030: an interval of 1e-6 s among 0.01 s ones.
      // cm/s^2 read as m/s^2 (the rows' unit here): 300 m/s^2 is 30.6 g.
      {"two_gal_read_as_mps2", F::TwoColumn, "0.00 120\n0.01 -300\n0.02 80\n", 2, "acceleration",
       "expected at most 20 g"},
      // Times in ms read as s: intervals of 10 s.
      {"two_times_in_ms", F::TwoColumn, "0 0.1\n10 0.2\n20 0.3\n", 2, "time", "got 10 s"},
      {"two_typo_time", F::TwoColumn, "0.00 1\n0.01 2\n0.02 3\n0.020001 4\n0.04 5\n", 4, "time", "mistyped"},
      {"two_eof_mark_inside", F::TwoColumn, "0.00 1\n\x1a\n0.01 2\n", 2, "value", "0x1A"},
  };
}

TEST(AccelerogramErrors, EveryMalformedInputNamesFileLineAndField) {
  TempDir dir;
  for (const BadInput& bad : bad_inputs()) {
    SCOPED_TRACE(bad.label);
    const fs::path file = dir.path() / (std::string(bad.label) + ".txt");
    if (bad.content != "<missing>") dir.write(file.filename().string(), bad.content);
    try {
      (void)fq::read_accelerogram(file, bad.format, fq::AccelerationUnit::MetrePerSecond2);
      ADD_FAILURE() << "no exception";
    } catch (const fq::InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(e.file(), file.string()) << msg;
      EXPECT_EQ(e.line(), bad.line) << msg;
      EXPECT_EQ(e.field(), bad.field) << msg;
      EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
      if (bad.line > 0) {
        EXPECT_NE(msg.find(":" + std::to_string(bad.line) + ":"), std::string::npos) << msg;
      }
      EXPECT_NE(msg.find(std::string("field '") + bad.field + "'"), std::string::npos) << msg;
      EXPECT_NE(msg.find(bad.also), std::string::npos) << msg;
      EXPECT_NE(msg.find("expected"), std::string::npos) << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "wrong exception type: " << e.what();
    }
  }
}

TEST(AccelerogramErrors, DirectoryIsRefused) {
  TempDir dir;
  EXPECT_THROW((void)fq::read_peer_at2(dir.path()), fq::InputError);
}

// ---- two-column reader ---------------------------------------------------------

TEST(TwoColumn, UniformFileIsReadExactly) {
  // Values exactly representable in binary, so "exactly" means bitwise.
  TempDir dir;
  const std::string text =
      "# Synthetic uniform record\n"
      "0.00  1.5\n"
      "\n"
      "0.01, -2.25\n"  // comma separated
      "  0.02\t0.125  \n"
      "# a comment between rows\n"
      "0.03 -0.5\n"
      "0.04 3\n";
  const fs::path file = dir.write("uniform.txt", text);
  const fq::AccelerationRecord rec = fq::read_two_column(file, fq::AccelerationUnit::MetrePerSecond2);
  EXPECT_EQ(rec.source, file.string());
  EXPECT_EQ(rec.acceleration_mps2, (std::vector<double>{1.5, -2.25, 0.125, -0.5, 3.0}));
  // dt = mean interval = 0.04 / 4; the printed times are nearest doubles, so
  // one or two ulps of 0.01 is all that may differ.
  EXPECT_NEAR(rec.dt_s, 0.01, 1e-16);
  EXPECT_EQ(rec.description.rfind("Synthetic uniform record", 0), 0u) << rec.description;
  EXPECT_EQ(rec.description.find("shifted"), std::string::npos) << rec.description;
  EXPECT_EQ(rec.description.find("resampled"), std::string::npos) << rec.description;
}

TEST(TwoColumn, NonzeroStartIsShiftedAndStated) {
  TempDir dir;
  const fq::AccelerationRecord rec =
      fq::read_two_column(dir.write("late.txt", "2.5 1\n2.51 2\n2.52 4\n"), fq::AccelerationUnit::MetrePerSecond2);
  EXPECT_EQ(rec.acceleration_mps2, (std::vector<double>{1.0, 2.0, 4.0}));
  EXPECT_NEAR(rec.dt_s, 0.01, 1e-15);
  EXPECT_NE(rec.description.find("shifted by -2.5 s"), std::string::npos) << rec.description;
  // Sample k is now at k * dt: the first value at t = 0.
  EXPECT_DOUBLE_EQ(rec.at(0.0), 1.0);
}

TEST(TwoColumn, NonUniformSamplesAreKeptWhereTheFilePutsThem) {
  // Times 0, .02, .05, .06 (intervals .02, .03, .01): the samples stay at
  // their times, dt_s is the smallest interval, and the motion between them
  // is linear. By hand: at .01 (1 + 3) / 2 = 2; at .03 3 + (1/3)(-3 - 3) = 1;
  // at .04 3 + (2/3)(-6) = -1; at .055 (-3 + 0) / 2 = -1.5.
  TempDir dir;
  const fq::AccelerationRecord rec = fq::read_two_column(
      dir.write("irregular.txt", "0.00 1\n0.02 3\n0.05 -3\n0.06 0\n"), fq::AccelerationUnit::MetrePerSecond2);
  EXPECT_NEAR(rec.dt_s, 0.01, 1e-15);
  EXPECT_EQ(rec.acceleration_mps2, (std::vector<double>{1.0, 3.0, -3.0, 0.0}));
  ASSERT_EQ(rec.sample_time_s.size(), 4u);
  EXPECT_EQ(rec.sample_time_s[0], 0.0);
  EXPECT_EQ(rec.sample_time_s[2], 0.05);
  EXPECT_NEAR(rec.duration_s(), 0.06, 1e-15);
  const std::pair<double, double> expected[] = {{0.0, 1.0},  {0.01, 2.0}, {0.02, 3.0},  {0.03, 1.0},
                                                {0.04, -1.0}, {0.05, -3.0}, {0.055, -1.5}, {0.06, 0.0}};
  for (const auto& [t, a] : expected) EXPECT_NEAR(rec.at(t), a, 1e-12) << t;  // rounding of printed times only
  EXPECT_EQ(rec.at(0.0601), 0.0);  // past the last sample: no motion
  EXPECT_NE(rec.description.find("kept as given"), std::string::npos) << rec.description;
}

TEST(TwoColumn, APeakBetweenTheSmallestIntervalsGridIsKept) {
  // The geometry probe's file: times 0, .010, .020, .027, .037, .047 with
  // 5 m/s^2 at .037 s. A grid of the smallest interval (.007 s) from t = 0
  // passes .035 and .042 and cut the peak to 4 m/s^2; the record's peak is
  // the file's sample.
  TempDir dir;
  const fq::AccelerationRecord rec = fq::read_two_column(
      dir.write("spike.txt", "0 0\n0.010 1\n0.020 2\n0.027 1\n0.037 5\n0.047 0\n"),
      fq::AccelerationUnit::MetrePerSecond2);
  double t = 0.0;
  EXPECT_EQ(rec.peak_mps2(&t), 5.0);
  EXPECT_NEAR(t, 0.037, 1e-15);
  EXPECT_NEAR(rec.at(0.037), 5.0, 1e-12);
  fq::GroundMotion gm;
  fq::GroundMotionComponent c;
  c.record = rec;
  gm.add_component(c);
  EXPECT_NEAR(gm.peak_abs_mps2().x(), 5.0, 1e-12);
}

TEST(TwoColumn, TimesRoundedInPrintAreUniformSampling) {
  // 300 samples per second with times printed to four decimals: intervals
  // of 0.0033 and 0.0034 s, each time within 1e-4 s (one unit of its last
  // digit) of the uniform grid. Read as uniform: the values as given and
  // dt = t_last / (n - 1) = 0.03 / 9, i.e. 1/300 s.
  TempDir dir;
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(4);
  for (int k = 0; k < 10; ++k) text << k / 300.0 << " " << (k == 6 ? 5.79 : 0.5 * k) << "\n";
  const fq::AccelerationRecord rec =
      fq::read_two_column(dir.write("rounded.txt", text.str()), fq::AccelerationUnit::MetrePerSecond2);
  EXPECT_TRUE(rec.sample_time_s.empty());
  EXPECT_NEAR(rec.dt_s, 1.0 / 300.0, 1e-15);
  ASSERT_EQ(rec.acceleration_mps2.size(), 10u);
  EXPECT_EQ(rec.acceleration_mps2[6], 5.79);
  EXPECT_NE(rec.description.find("read as uniform"), std::string::npos) << rec.description;
}

TEST(TwoColumn, UnitsGAndCentimetrePerSecondSquared) {
  // 1 g = 9.80665 m/s^2 (standard gravity, the PEER convention);
  // 1 cm/s^2 = 0.01 m/s^2.
  TempDir dir;
  // (Values a ground motion can have in each unit: 2.5 g, 2.5 m/s^2, 2.5 cm/s^2.)
  const fs::path file = dir.write("units.txt", "0 1\n0.01 -0.5\n0.02 2.5\n");
  const fq::AccelerationRecord in_g = fq::read_two_column(file, fq::AccelerationUnit::G);
  EXPECT_DOUBLE_EQ(in_g.acceleration_mps2[0], 9.80665);
  EXPECT_DOUBLE_EQ(in_g.acceleration_mps2[1], -0.5 * 9.80665);
  EXPECT_DOUBLE_EQ(in_g.acceleration_mps2[2], 2.5 * 9.80665);
  const fq::AccelerationRecord in_gal = fq::read_two_column(file, fq::AccelerationUnit::CentimetrePerSecond2);
  EXPECT_DOUBLE_EQ(in_gal.acceleration_mps2[0], 0.01);
  EXPECT_DOUBLE_EQ(in_gal.acceleration_mps2[1], -0.005);
  EXPECT_DOUBLE_EQ(in_gal.acceleration_mps2[2], 0.025);
  EXPECT_NE(in_gal.description.find("cm/s2"), std::string::npos) << in_gal.description;
  // The dispatcher's default unit is m/s^2.
  EXPECT_DOUBLE_EQ(fq::read_accelerogram(file, fq::RecordFormat::TwoColumn).acceleration_mps2[2], 2.5);
}

TEST(TwoColumn, ReadsTheJmaKobeRecordWrittenAsTwoColumnsInGal) {
  // Two readers of the same data must agree: KJM000 written out as
  // "time acceleration[cm/s^2]" starting at t = 10 s, read back as cm/s2.
  TempDir dir;
  const fq::AccelerationRecord at2 = fq::read_peer_at2(kGroundMotions / "RSN1106_KOBE_KJM000.AT2");
  std::ostringstream out;
  out.precision(17);
  for (std::size_t k = 0; k < at2.acceleration_mps2.size(); ++k)
    out << 10.0 + 0.02 * double(k) << ' ' << at2.acceleration_mps2[k] * 100.0 << '\n';
  const fq::AccelerationRecord two =
      fq::read_two_column(dir.write("kjm000.txt", out.str()), fq::AccelerationUnit::CentimetrePerSecond2);
  ASSERT_EQ(two.acceleration_mps2.size(), at2.acceleration_mps2.size());
  EXPECT_NEAR(two.dt_s, 0.02, 1e-12);
  for (std::size_t k = 0; k < at2.acceleration_mps2.size(); ++k)
    ASSERT_NEAR(two.acceleration_mps2[k], at2.acceleration_mps2[k], 1e-12 * kG) << k;
}

// ---- names ---------------------------------------------------------------------

TEST(AccelerogramNames, FormatAndUnitNamesRoundTrip) {
  for (const fq::RecordFormat f : {fq::RecordFormat::PeerAt2, fq::RecordFormat::TwoColumn}) {
    fq::RecordFormat back{};
    ASSERT_TRUE(fq::parse_record_format(fq::record_format_name(f), back));
    EXPECT_EQ(back, f);
  }
  for (const fq::AccelerationUnit u :
       {fq::AccelerationUnit::G, fq::AccelerationUnit::MetrePerSecond2, fq::AccelerationUnit::CentimetrePerSecond2}) {
    fq::AccelerationUnit back{};
    ASSERT_TRUE(fq::parse_acceleration_unit(fq::acceleration_unit_name(u), back));
    EXPECT_EQ(back, u);
  }
  EXPECT_STREQ(fq::record_format_name(fq::RecordFormat::PeerAt2), "peer_at2");
  EXPECT_STREQ(fq::record_format_name(fq::RecordFormat::TwoColumn), "two_column");
  fq::RecordFormat f = fq::RecordFormat::TwoColumn;
  EXPECT_FALSE(fq::parse_record_format("AT2", f));
  EXPECT_EQ(f, fq::RecordFormat::TwoColumn);  // untouched on failure
  fq::AccelerationUnit u = fq::AccelerationUnit::G;
  EXPECT_FALSE(fq::parse_acceleration_unit("gal", u));
  EXPECT_EQ(u, fq::AccelerationUnit::G);
  EXPECT_EQ(fq::acceleration_unit_to_mps2(fq::AccelerationUnit::G), 9.80665);
  EXPECT_EQ(fq::acceleration_unit_to_mps2(fq::AccelerationUnit::MetrePerSecond2), 1.0);
  EXPECT_EQ(fq::acceleration_unit_to_mps2(fq::AccelerationUnit::CentimetrePerSecond2), 0.01);
}
