#include "io/folder_lock.h"

#include <cerrno>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "io/run_output.h"

namespace fq {

FolderLock::FolderLock(const std::filesystem::path& folder) {
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0)
    throw OutputError("cannot open output folder '" + folder.string() + "': " +
                      std::generic_category().message(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    release();
    if (err == EWOULDBLOCK)
      throw OutputError("output folder '" + folder.string() +
                        "' is in use by another framequake process (a run, resume, compare or sweep writing "
                        "there now); wait for it to end or choose another folder");
    throw OutputError("cannot lock output folder '" + folder.string() + "': " + std::generic_category().message(err));
  }
}

FolderLock::FolderLock(FolderLock&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }

FolderLock& FolderLock::operator=(FolderLock&& o) noexcept {
  if (this != &o) {
    release();
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

FolderLock::~FolderLock() { release(); }

void FolderLock::release() noexcept {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor drops the lock
  fd_ = -1;
}

}  // namespace fq
