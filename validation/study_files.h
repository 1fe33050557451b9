// Results files of the validation studies, written whole or not at all.
//
// A study runs for seconds to minutes and then writes a CSV and a markdown
// table. Each file goes to ".<name>.tmp" beside the target, is checked
// (disk full, no permission, missing folder) and then renamed over the
// target, so a failed write leaves the previous results untouched and says
// which file it could not write.
#pragma once

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace fq::validation {

inline void write_study_file(const std::filesystem::path& target, const std::string& content) {
  // Built by appending: gcc 12 warns falsely (-Wrestrict, its bug 105651)
  // about "." + std::string once inlined, and CI treats warnings as errors.
  std::string hidden_name(1, '.');
  hidden_name += target.filename().string();
  hidden_name += ".tmp";
  const std::filesystem::path temporary = target.parent_path() / hidden_name;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open '" + temporary.string() + "' for writing");
    out << content;
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error("cannot write '" + temporary.string() + "' (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error("cannot rename '" + temporary.string() + "' to '" + target.string() + "': " + ec.message());
  }
}

}  // namespace fq::validation
