// libFuzzer target: the accelerogram readers (PEER .AT2 and two-column) on
// arbitrary bytes. The first byte picks the reader (and the unit of a
// two-column file); the rest is the file. Bad input must end in
// fq::InputError; a record that is accepted must satisfy the contract of
// accelerogram.h (at least 2 samples, positive finite dt, finite values) or
// the target aborts.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "fuzz_scratch.h"
#include "io/accelerogram.h"
#include "io/input_error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t selector = data[0];
  static const std::filesystem::path file = fq_fuzz::scratch_dir() / "record.txt";
  fq_fuzz::write_bytes(file, data + 1, size - 1);
  const fq::AccelerationUnit units[] = {fq::AccelerationUnit::G, fq::AccelerationUnit::MetrePerSecond2,
                                        fq::AccelerationUnit::CentimetrePerSecond2};
  const fq::RecordFormat format = (selector & 1) ? fq::RecordFormat::TwoColumn : fq::RecordFormat::PeerAt2;
  try {
    const fq::AccelerationRecord rec = fq::read_accelerogram(file, format, units[(selector >> 1) % 3]);
    if (rec.acceleration_mps2.size() < 2 || !(rec.dt_s > 0.0) || !std::isfinite(rec.dt_s)) std::abort();
    for (const double a : rec.acceleration_mps2)
      if (!std::isfinite(a)) std::abort();
  } catch (const fq::InputError&) {
  }
  return 0;
}
