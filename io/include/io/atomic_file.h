// Files that a reader sees either whole or not at all (used by io, the
// command line and the validation studies).
//
// A file is written under a temporary name in the same folder (so the rename
// never crosses a file system), closed, and then renamed over the target.
// POSIX rename is atomic: a viewer, or a run that crashed a microsecond
// later, finds the old complete file or the new complete one, never a
// half-written one (DESIGN.md "Output a user can open").
//
// What this does not cover: the machine losing power. Guarding against that
// needs an fsync before each rename, which measured 5-6 ms per call here
// (ext4): two per frame made writing the 1 s falling-block demo's 51 frames
// cost 0.57 s, more than four times its whole step loop. A process crash
// (instability, exception, kill, out of memory) is the failure a simulation
// meets; the page cache survives it, so the rename is enough.
//
// Temporary names start with '.' and end with ".tmp" so that file dialogs
// hide them and a later run recognises them as its own leftovers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace fq::detail {

// ".<name>.tmp" next to `target`.
std::filesystem::path temporary_path_for(const std::filesystem::path& target);

// Renames the complete, closed file `temporary` to `target`. Throws
// std::runtime_error naming both files on failure.
void commit_file(const std::filesystem::path& temporary, const std::filesystem::path& target);

// Writes `content` to a temporary file and commits it to `target`. Throws
// std::runtime_error naming the file when it cannot; the temporary is then
// removed and `target` is left as it was.
void write_file_atomically(const std::filesystem::path& target, std::string_view content);

// Cuts an appended text file (history.csv, events.csv) back to the end of
// its last complete line, after a write into it failed part-way (a full
// disk): a reader then finds whole rows only. Best effort, never throws; a
// file without any line end is left as it is.
void cut_back_to_last_line_end(const std::filesystem::path& file) noexcept;

// Line ends ('\n') in `file`, or -1 when it cannot be read. Never throws.
std::int64_t count_line_ends(const std::filesystem::path& file) noexcept;

// The reason the C library gives for the last failed call (errno), for
// messages about files that could not be created or written.
std::string last_system_error();

}  // namespace fq::detail
