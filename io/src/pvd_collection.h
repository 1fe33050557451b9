// Private to io: the ParaView collection file (case.pvd) that lists the
// frames with their physical time, so ParaView's time slider shows seconds.
//
// The whole file is rewritten atomically (atomic_file.h) after each frame, so
// at every instant it is valid XML listing only frames that are complete on
// disk. Rewriting costs O(frames) bytes per frame; at the default 50 frames
// per simulated second a 20 s run ends with a ~80 kB file, well below the
// cost of one frame.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace fq::detail {

class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path pvd_file);

  // Appends a data set (time in s, file relative to the .pvd's folder) and
  // rewrites the file. Call only once `relative_file` is complete on disk.
  void add(double time_s, const std::string& relative_file);
  // Rewrites the file with the entries so far (an empty collection is valid).
  void write() const;

  std::size_t size() const { return count_; }
  // The <DataSet .../> lines so far, and setting them back (checkpoint
  // resume; `count` data sets).
  const std::string& entries() const { return entries_; }
  void restore(std::string entries, std::size_t count) {
    entries_ = std::move(entries);
    count_ = count;
  }
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::string entries_;  // the <DataSet .../> lines so far
  std::size_t count_ = 0;
};

}  // namespace fq::detail
