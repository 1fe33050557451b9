// Checkpoint files: DIR/checkpoint.bin, the full state of a run, from which
// `framequake resume DIR` continues bitwise as the run would have.
//
// File layout (version 3; all integers in the writing machine's byte order,
// which the marker field pins down):
//   offset 0   8 bytes  magic "FQCKPT\r\n" (the CR LF catches text-mode copies)
//   offset 8   u32      format version (kCheckpointFormatVersion)
//   offset 12  u32      byte-order marker 0x01020304
//   offset 16  u64      payload length in bytes
//   offset 24  payload  (below)
//   end - 8    u64      FNV-1a 64 of the payload (damage check)
// Payload, written with dem_core/state_io.h, sections in this order:
//   "run"      case file (absolute path), the files the case reads, each
//              with its fingerprint (case_file_fingerprints: count, then
//              what, path, hash),
//              checkpoint interval (s), --force flag, case name, step, time (s)
//   "output"   what the output folder held at the checkpoint (RunOutput::save_state:
//              frames listed in case.pvd, byte lengths and row counts of
//              history.csv and events.csv)
//   "storeys"  each storey's peak drift ratios (x, y, magnitude), the time
//              of the peak, the collapse time, the final drift, the peaks of
//              its column, floor drift, top and base slips and twist, and
//              the residual's block sums (StoreyDriftMonitor::save_state)
//   simulation state (Simulation::save_state: bodies, ledger, events,
//              bonded pairs, then each force provider's own state)
// The file is written under a temporary name and renamed (atomic_file.h), so
// a run killed while writing leaves the previous checkpoint intact.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/case_def.h"

namespace fq {

// Version 2: a CUREE spring's state holds whether it has passed delta_p.
// Version 3: the storeys' peaks and residual, taken at every step, follow
// the output section.
// Version 4: each storey's record adds its peak floor drift, base slip and
// twist.
// Version 5: the residual's window is in record seconds (its blocks are
// of another length than a version 4 file's).
// Version 6: each storey's record adds its peak top slip (the floor's
// movement off its column tops), and its base slip and floor drift are
// taken from the floor's own points.
// Version 7: the run section keeps each case file's and record's own
// fingerprint instead of one over all of them, so that a refused resume
// names the file that changed.
inline constexpr std::uint32_t kCheckpointFormatVersion = 7;
inline constexpr const char* kCheckpointFileName = "checkpoint.bin";

// A checkpoint file that cannot be used: missing, damaged, truncated,
// foreign, of another format version, or written for another case. The
// message names the file and what is wrong.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Frames `payload` (header, checksum) and writes it atomically to `file`.
// Throws std::runtime_error when the file cannot be written.
void write_checkpoint_file(const std::filesystem::path& file, const std::string& payload);

// Reads `file` and checks magic, version, byte order, length and checksum;
// returns the payload. Throws CheckpointError naming the file otherwise.
std::string read_checkpoint_file(const std::filesystem::path& file);

// One file a case reads, with the FNV-1a 64 of its length and bytes.
struct CaseFileFingerprint {
  std::string what;             // "case file" or "ground-motion record"
  std::filesystem::path file;   // absolute
  std::uint64_t hash = 0;
};

// The case file, then each ground-motion record in the case's order, each
// with its own fingerprint: a resumed run refuses a case that changed in
// any byte of any of them, and says which. Throws CheckpointError when
// one of the files cannot be read.
std::vector<CaseFileFingerprint> case_file_fingerprints(const CaseDef& def);

// In words, how `now` differs from `then`, file by file in their order
// (the case file, then the records): "the case file 'a.yaml' has
// changed", "the ground-motion record 'c.AT2' differs from the one the run
// began with ('b.AT2')", "the case now reads the ground-motion record
// 'c.AT2' as well", "the case no longer reads ...", joined by "; ". Empty
// when every file has its fingerprint of then.
std::string changed_case_files(const std::vector<CaseFileFingerprint>& then,
                               const std::vector<CaseFileFingerprint>& now);

}  // namespace fq
