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
//
// A file system without flock (some network and FUSE mounts: ENOLCK,
// EOPNOTSUPP, ENOSYS) is no reason to refuse every run: the lock then goes
// on without being held and warning() says so, for the caller to pass on
// once (the folder is then unprotected against a second process).
//
// For the tests only: FQ_TEST_FLOCK_ERRNO=N (a number) makes every lock act
// as if flock had failed with errno N, for the file systems a test machine
// does not have. Nothing else reads it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace fq {

class FolderLock {
 public:
  FolderLock() = default;
  // Locks the existing folder `folder`. Throws OutputError (run_output.h)
  // saying the folder "is in use by another framequake process" when
  // another process holds it, or naming the folder and the system's reason
  // when it cannot be opened or locked, except on a file system without
  // locks (see above).
  explicit FolderLock(const std::filesystem::path& folder);
  FolderLock(FolderLock&& o) noexcept;
  FolderLock& operator=(FolderLock&& o) noexcept;
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock();

  // Empty when the lock is held (or none was taken); else the warning that
  // the folder's file system has no locks and the folder is unprotected.
  const std::string& warning() const { return warning_; }

 private:
  void release() noexcept;
  int fd_ = -1;
  std::string warning_;
};

// Whether `text` is a FolderLock::warning() (a study, having said it once
// for its folder, does not repeat it under each of its runs).
bool is_folder_lock_warning(std::string_view text);

}  // namespace fq
