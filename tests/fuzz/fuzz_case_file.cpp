// libFuzzer target: fq::load_case_file on arbitrary bytes.
//
// The case file sits in a scratch folder next to `ground_motions/` (a link to
// the repository's cases/ground_motions) and a small valid record `rec.AT2`,
// so fuzzed text derived from the seeds (cases/*.yaml) can still reach the
// record-reading and window checks. Any fq::InputError is the expected
// outcome for bad text; any other exception, crash, leak or sanitizer report
// is a bug.
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "fuzz_scratch.h"
#include "io/case_file.h"
#include "io/input_error.h"

namespace {

const std::filesystem::path& case_path() {
  static const std::filesystem::path p = [] {
    namespace fs = std::filesystem;
    const fs::path dir = fq_fuzz::scratch_dir();
    std::error_code ec;
    fs::create_directory_symlink(fs::path(FQ_SOURCE_DIR) / "cases" / "ground_motions", dir / "ground_motions", ec);
    std::ofstream(dir / "rec.AT2") << "PEER NGA STRONG MOTION DATABASE RECORD\n"
                                      "fuzz seed record\n"
                                      "ACCELERATION TIME SERIES IN UNITS OF G\n"
                                      "NPTS=    6, DT=   .0100 SEC\n"
                                      "  .1E-02  .2E-02 -.1E-02  .0E+00  .3E-02\n"
                                      "  .1E-02\n";
    return dir / "case.yaml";
  }();
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fq_fuzz::write_bytes(case_path(), data, size);
  try {
    const fq::CaseDef def = fq::load_case_file(case_path());
    (void)def;
  } catch (const fq::InputError&) {
    // Refused with file, line and field: the contract for bad input.
  }
  return 0;
}
