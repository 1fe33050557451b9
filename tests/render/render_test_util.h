// Helpers shared by the render tests: the independent GIF reader (Pillow in
// /usr/bin/python3) and small JSON field extraction from its output.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fq_test {

// A fresh empty folder under the system temp folder, removed on destruction.
class ScratchDir {
 public:
  ScratchDir() {
    std::string templ = (std::filesystem::temp_directory_path() / "fq_render_XXXXXX").string();
    if (!mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    path_ = templ;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline bool pil_available() {
  return std::system("/usr/bin/python3 -c 'import PIL.Image' > /dev/null 2>&1") == 0;
}

struct GifInfo {
  int n_frames = -1, width = -1, height = -1;
  std::string json;
};

inline int json_int(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return -1;
  return std::atoi(json.c_str() + at + key.size() + 4);
}

// Reads `gif` with Pillow; with raw_folder, also dumps frames as RGB bytes.
inline GifInfo read_gif_with_pil(const std::filesystem::path& gif, const std::filesystem::path& raw_folder = {}) {
  // Appended piece by piece: gcc 12 warns falsely (-Warray-bounds, its bug
  // 105651 family) about the inlined concatenation of string temporaries.
  const std::filesystem::path script = std::filesystem::path(FQ_SOURCE_DIR) / "tests/render/read_gif_with_pil.py";
  std::string cmd = "/usr/bin/python3 '";
  cmd += script.string();
  cmd += "' '";
  cmd += gif.string();
  cmd += "'";
  if (!raw_folder.empty()) cmd += " '" + raw_folder.string() + "'";
  GifInfo info;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return info;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) info.json.append(buf, n);
  if (pclose(p) != 0) return info;
  info.n_frames = json_int(info.json, "n_frames");
  info.width = json_int(info.json, "width");
  info.height = json_int(info.json, "height");
  return info;
}

inline std::vector<unsigned char> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<unsigned char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace fq_test
