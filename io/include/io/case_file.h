// Reader of framequake case files (YAML, schema version 1; the reference is
// cases/README.md). The reader is strict: every problem throws fq::InputError
// naming the file, the 1-based line, the full field path (for example
// `members[3].section`) and what was expected. It refuses YAML syntax errors,
// unknown keys (listing the keys allowed there), keys given twice, missing
// required fields, wrong types (a quoted string or text where a number is
// expected, a scalar where a list is), non-finite numbers, non-positive
// dimensions, densities and time steps, duplicate ids and names, members
// whose two nodes are the same or coincide, references to unknown nodes,
// sections and materials, ground-motion files that do not exist, windows
// that start beyond the end of a record, and unknown schema versions.
//
// The accelerograms are read while loading, so a bad record fails here with
// the reader's own file, line and field (accelerogram.h).
#pragma once

#include <filesystem>

#include "io/case_def.h"

namespace fq {

// Reads and validates a case file. Relative ground-motion `file:` paths are
// resolved against the case file's folder; the output folder stays as
// written (relative to the working directory of the run).
CaseDef load_case_file(const std::filesystem::path& file);

}  // namespace fq
