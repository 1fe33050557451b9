#include "io/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace fq::detail {

namespace fs = std::filesystem;

fs::path temporary_path_for(const fs::path& target) {
  // Appended, not "." + name: gcc 12 at -O3 warns falsely (-Wrestrict).
  std::string hidden_name(1, '.');
  hidden_name += target.filename().string();
  hidden_name += ".tmp";
  return target.parent_path() / hidden_name;
}

void commit_file(const fs::path& temporary, const fs::path& target) {
  std::error_code ec;
  fs::rename(temporary, target, ec);
  if (ec) throw std::runtime_error("cannot rename '" + temporary.string() + "' to '" + target.string() + "': " + ec.message());
}

void write_file_atomically(const fs::path& target, std::string_view content) {
  const fs::path tmp = temporary_path_for(target);
  // A write or rename that fails leaves no temporary behind: the caller
  // reports the error and the target keeps its previous content.
  const auto drop_temporary = [&tmp] {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  };
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create '" + tmp.string() + "': " + last_system_error());
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) {
      drop_temporary();
      throw std::runtime_error("cannot write '" + tmp.string() + "' (disk full?)");
    }
  }
  try {
    commit_file(tmp, target);
  } catch (const std::runtime_error&) {
    drop_temporary();
    throw;
  }
}

std::string last_system_error() {
  const int code = errno;
  return code != 0 ? std::string(std::strerror(code)) : std::string("reason unknown");
}

std::int64_t count_line_ends(const fs::path& file) noexcept {
  try {
    std::ifstream in(file, std::ios::binary);
    if (!in) return -1;
    std::vector<char> block(1 << 16);
    std::int64_t count = 0;
    while (in) {
      in.read(block.data(), std::streamsize(block.size()));
      const std::streamsize n = in.gcount();
      for (std::streamsize k = 0; k < n; ++k) count += block[std::size_t(k)] == '\n';
    }
    return count;
  } catch (...) {
    return -1;
  }
}

void cut_back_to_last_line_end(const fs::path& file) noexcept {
  try {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec || size == 0) return;
    std::ifstream in(file, std::ios::binary);
    if (!in) return;
    // Backwards in blocks: the last line end is near the end.
    constexpr std::uintmax_t kBlock = 4096;
    std::vector<char> block(kBlock);
    std::uintmax_t end = size;
    while (end > 0) {
      const std::uintmax_t begin = end > kBlock ? end - kBlock : 0;
      const std::size_t n = std::size_t(end - begin);
      in.seekg(std::streamoff(begin));
      in.read(block.data(), std::streamsize(n));
      if (in.gcount() != std::streamsize(n)) return;
      for (std::size_t k = n; k-- > 0;) {
        if (block[k] == '\n') {
          const std::uintmax_t keep = begin + k + 1;
          in.close();
          if (keep < size) fs::resize_file(file, keep, ec);
          return;
        }
      }
      end = begin;
    }
  } catch (...) {
    // Best effort: the caller is already reporting a failure.
  }
}

}  // namespace fq::detail
