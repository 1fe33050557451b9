// Readers for recorded accelerograms: PEER NGA .AT2 files and plain
// two-column "time acceleration" text. Both return an fq::AccelerationRecord
// (dem_core/ground_motion.h): first sample at t = 0, acceleration in m/s^2,
// uniformly sampled (a non-uniform two-column file keeps its sample times).
//
// Every malformed input throws fq::InputError naming the file, the 1-based
// line (0 for the file as a whole), the field and what was expected. Fields:
//   "file"          missing, unreadable or empty file (line 0)
//   "header"        AT2 header lines 1-4 missing, wrong units, non-text bytes there
//   "NPTS", "DT"    AT2 line 4 (and NPTS also when the value count differs)
//   "value"         a data token that is not a finite number or rounds to 0
//                   (1e-400; subnormals are read), non-text bytes,
//                   wrong column count, fewer than 2 samples
//   "time", "acceleration"  the two columns of a two-column file
//
// Both readers accept LF, CRLF and CR line ends, a leading UTF-8 byte-order
// mark, a trailing DOS end-of-file mark (0x1A), Fortran E-format numbers
// with or without a leading digit ("-.1416764E-03") and Fortran D exponents
// ("1.5D-03"). Text kept from a file (an AT2 header's line 2, a two-column
// file's first comment) and text quoted in messages is UTF-8: a line that
// is not valid UTF-8 is read as Latin-1.
#pragma once

#include <filesystem>
#include <string>

#include "dem_core/ground_motion.h"

namespace fq {

enum class RecordFormat { PeerAt2, TwoColumn };

// The largest ground acceleration a record may hold, and a record times its
// amplitude scale may reach (g): five times the largest ever recorded
// (accelerogram.cpp). A scale that passes it (100 for a percentage) is as
// sure a mistake as a record in the wrong unit.
inline constexpr double kMaxAbsAcceleration_g = 20.0;
// Why `record` times `amplitude_scale` is refused (its peak beyond
// kMaxAbsAcceleration_g), or "" when it is not.
std::string scaled_record_problem(const AccelerationRecord& record, double amplitude_scale);

// "peer_at2" | "two_column"; false (out untouched) if unknown.
bool parse_record_format(const std::string& name, RecordFormat& out);
const char* record_format_name(RecordFormat f);

// Units a two-column file's acceleration column is in.
enum class AccelerationUnit { G, MetrePerSecond2, CentimetrePerSecond2 };

// "g" | "m/s2" | "cm/s2"; false (out untouched) if unknown.
bool parse_acceleration_unit(const std::string& name, AccelerationUnit& out);
// Inverse of parse_acceleration_unit.
const char* acceleration_unit_name(AccelerationUnit u);
// Factor from the unit to m/s^2: g -> kStandardGravity_mps2 (9.80665, the
// value PEER uses), cm/s2 -> 0.01.
double acceleration_unit_to_mps2(AccelerationUnit u);

// PEER NGA .AT2: 4 header lines, then NPTS values in g, any number per line
// (PEER writes 5; the last line may be partial).
//   line 1  database banner (not checked)
//   line 2  event, date, station, component -> description (trimmed; text
//           that is not valid UTF-8 is read as Latin-1 and converted, so
//           "D\xfczce" from an older file becomes "Düzce")
//   line 3  "ACCELERATION TIME SERIES IN UNITS OF G"; if it names units
//           ("UNITS OF X") they must be G, so a velocity (.VT2) or
//           displacement (.DT2) file given by mistake is refused
//   line 4  NPTS and DT, in one of three layouts:
//           - NGA keywords: "NPTS=   7500, DT=   .0200 SEC,",
//             "NPTS =   7500 , DT =   .020 SEC ,", "NPTS=   2000  DT=   .0200 SEC",
//             "DT= .0100 SEC, NPTS= 5372" (keywords case-insensitive, in
//             either order, spaces around '=' and the comma optional);
//           - older PEER files, numbers then names: "  5372    0.0100    NPTS, DT"
//             (or "... DT, NPTS" with the numbers in that order);
//           - two bare numbers "5372 0.0100", read only when unambiguous:
//             a whole number (NPTS), then a number with a decimal point or
//             an exponent (DT).
//           Every layout's NPTS must be a whole number >= 2 and DT a positive
//           finite time step in s; a line in none of them is refused with
//           a message that lists them. A unit after DT, glued or as the
//           next word, must be SEC, SECS, S or SECONDS (any case, or none):
//           "DT= .5 MSEC" is refused, not read as 0.5 s. A key given twice
//           ("NPTS= 6, DT= .01 SEC, NPTS= 7") is refused.
// A DOS end-of-file mark (0x1A, Ctrl-Z) as the file's last byte(s) is
// ignored (old DOS-written files end so); elsewhere it is a non-text byte.
// The count of values must equal NPTS exactly: a short or long file means a
// truncated or concatenated download, which must not pass silently.
// source = file as given; dt_s = DT; values converted with 9.80665 m/s^2 per g.
AccelerationRecord read_peer_at2(const std::filesystem::path& file);

// Plain text, one "time acceleration" pair per line, separated by whitespace
// or one comma; blank lines and lines starting with '#' are skipped. Time in
// s, strictly increasing; acceleration in `unit`.
//
// Sampling. If every interval is within a relative 1e-6 of the first one, or
// every time is within one unit of its last printed digit of the uniform
// grid t_0 + k (t_last - t_0)/(n - 1) (1/300 s printed to four decimals),
// the record is uniform and dt_s is the mean interval (t_last - t_0)/(n - 1),
// which averages out the rounding of printed times; the values are taken as
// they are. Otherwise the samples are kept where the file puts them
// (AccelerationRecord::sample_time_s, dt_s their smallest interval) and the
// ground motion is linear between them: a digitised record's samples are
// where its trace bends, and a grid would cut the peaks between its points.
// A file whose smallest interval is more than 100 times finer than its mean
// interval is refused (field "time", at the line of that interval): real
// irregular sampling does not span such a range, a mistyped time does.
//
// The first time need not be 0: the record is shifted so its first sample is
// at t = 0, and the shift is stated in `description`. description = the text
// of the first '#' comment line (if any) followed by notes on the unit, the
// shift and any non-uniform sampling.
AccelerationRecord read_two_column(const std::filesystem::path& file, AccelerationUnit unit);

// Dispatch on `format`; two_column_unit is used only for TwoColumn.
AccelerationRecord read_accelerogram(const std::filesystem::path& file, RecordFormat format,
                                     AccelerationUnit two_column_unit = AccelerationUnit::MetrePerSecond2);

}  // namespace fq
