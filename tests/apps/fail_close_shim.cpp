// Test helper, preloaded into `framequake` (LD_PRELOAD): the close of a file
// whose path ends in $FQ_FAIL_CLOSE_SUFFIX reports EIO, as a file system
// that finds a write it could not complete only at close does (NFS, a
// quota). A write to /dev/full fails earlier, at the flush. The real close
// runs first: the kernel releases the descriptor even when close fails.
// Both fclose (std::ofstream closes through it) and close are covered.
#include <dlfcn.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace {

bool is_target(int fd) {
  const char* suffix = std::getenv("FQ_FAIL_CLOSE_SUFFIX");
  if (suffix == nullptr || *suffix == '\0' || fd < 0) return false;
  char link[64];
  std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  char path[4096];
  const ssize_t n = readlink(link, path, sizeof path);
  return n > 0 && std::string_view(path, std::size_t(n)).ends_with(suffix);
}

template <typename F>
F real(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" int fclose(FILE* file) {
  static const auto real_fclose = real<int (*)(FILE*)>("fclose");
  const bool fail = file != nullptr && is_target(fileno(file));
  const int rc = real_fclose(file);
  if (!fail || rc != 0) return rc;
  errno = EIO;
  return EOF;
}

extern "C" int close(int fd) {
  static const auto real_close = real<int (*)(int)>("close");
  const bool fail = is_target(fd);
  const int rc = real_close(fd);
  if (!fail || rc != 0) return rc;
  errno = EIO;
  return -1;
}
