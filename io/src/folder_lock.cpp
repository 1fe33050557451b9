#include "io/folder_lock.h"

#include <cerrno>
#include <cstdlib>
#include <string>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "io/run_output.h"

namespace fq {

namespace {

constexpr std::string_view kNoLocksWarningStart = "cannot lock output folder '";

// flock's errors that mean "this file system has no locks", not "someone
// else holds it" or "something is wrong".
bool file_system_has_no_locks(int err) { return err == ENOLCK || err == EOPNOTSUPP || err == ENOTSUP || err == ENOSYS; }

// flock, or the failure FQ_TEST_FLOCK_ERRNO stands in for (tests only; see
// the header). Returns 0 or the errno.
int try_flock(int fd) {
  if (const char* forced = std::getenv("FQ_TEST_FLOCK_ERRNO"); forced != nullptr && *forced != '\0')
    return std::atoi(forced);
  return ::flock(fd, LOCK_EX | LOCK_NB) == 0 ? 0 : errno;
}

}  // namespace

bool is_folder_lock_warning(std::string_view text) {
  return text.starts_with(kNoLocksWarningStart) && text.find("going on without the lock") != std::string_view::npos;
}

FolderLock::FolderLock(const std::filesystem::path& folder) {
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0)
    throw OutputError("cannot open output folder '" + folder.string() + "': " +
                      std::generic_category().message(errno));
  if (const int err = try_flock(fd_); err != 0) {
    release();
    if (file_system_has_no_locks(err)) {
      warning_ = std::string(kNoLocksWarningStart) + folder.string() + "': " + std::generic_category().message(err) +
                 " (its file system has no file locks); going on without the lock, so another framequake process "
                 "writing there at the same time would not be stopped";
      return;
    }
    if (err == EWOULDBLOCK)
      throw OutputError("output folder '" + folder.string() +
                        "' is in use by another framequake process (a run, resume, compare or sweep writing "
                        "there now); wait for it to end or choose another folder");
    throw OutputError("cannot lock output folder '" + folder.string() + "': " + std::generic_category().message(err));
  }
}

FolderLock::FolderLock(FolderLock&& o) noexcept : fd_(o.fd_), warning_(std::move(o.warning_)) { o.fd_ = -1; }

FolderLock& FolderLock::operator=(FolderLock&& o) noexcept {
  if (this != &o) {
    release();
    fd_ = o.fd_;
    o.fd_ = -1;
    warning_ = std::move(o.warning_);
  }
  return *this;
}

FolderLock::~FolderLock() { release(); }

void FolderLock::release() noexcept {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor drops the lock
  fd_ = -1;
}

}  // namespace fq
