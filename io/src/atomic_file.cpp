#include "io/atomic_file.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

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
    if (!out) throw std::runtime_error("cannot create '" + tmp.string() + "'");
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

}  // namespace fq::detail
