// An exclusive advisory lock (flock) on an output folder itself, held for
// the life of the object: a second run, resume or study writing into the
// same folder at the same time is refused instead of interleaving its files
// with the first (a CLI probe's two runs into one folder left a summary
// saying "completed" over a history.csv of a fifth of its rows; two
// compares into one --out each wrote comparison.csv, the last one won).
// RunOutput holds one on its run's folder, compare and sweep one on their
// --out folder for the whole study. The kernel drops the lock when the
// process ends, however it ends, so a killed process leaves no stale lock;
// nothing is written into the folder. The descriptor is close-on-exec, so
// a child (the figure script) does not keep the lock alive.
#pragma once

#include <filesystem>

namespace fq {

class FolderLock {
 public:
  FolderLock() = default;
  // Locks the existing folder `folder`. Throws OutputError (run_output.h)
  // saying the folder "is in use by another framequake process" when
  // another process holds it, or naming the folder and the system's reason
  // when it cannot be opened or locked.
  explicit FolderLock(const std::filesystem::path& folder);
  FolderLock(FolderLock&& o) noexcept;
  FolderLock& operator=(FolderLock&& o) noexcept;
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock();

 private:
  void release() noexcept;
  int fd_ = -1;
};

}  // namespace fq
