#include "io/checkpoint.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/atomic_file.h"

namespace fq {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'F', 'Q', 'C', 'K', 'P', 'T', '\r', '\n'};
constexpr std::uint32_t kByteOrderMarker = 0x01020304u;
constexpr std::size_t kHeaderBytes = 24;
constexpr std::size_t kTrailerBytes = 8;

std::uint64_t fnv1a(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    h ^= static_cast<unsigned char>(data[k]);
    h *= 1099511628211ull;
  }
  return h;
}
constexpr std::uint64_t kFnvBasis = 1469598103934665603ull;

template <class T>
void append_pod(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T read_pod(const std::string& bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

bool read_whole_file(const fs::path& file, std::string& out) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;  // a pipe would block the open (see accelerogram.cpp)
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) return false;
  out = s.str();
  return true;
}

}  // namespace

void write_checkpoint_file(const fs::path& file, const std::string& payload) {
  std::string doc;
  doc.reserve(kHeaderBytes + payload.size() + kTrailerBytes);
  doc.append(kMagic, sizeof kMagic);
  append_pod(doc, kCheckpointFormatVersion);
  append_pod(doc, kByteOrderMarker);
  append_pod(doc, std::uint64_t(payload.size()));
  doc += payload;
  append_pod(doc, fnv1a(kFnvBasis, payload.data(), payload.size()));
  detail::write_file_atomically(file, doc);
}

std::string read_checkpoint_file(const fs::path& file) {
  const std::string name = "checkpoint file '" + file.string() + "'";
  std::error_code ec;
  if (!fs::exists(file, ec)) throw CheckpointError(name + " does not exist (was the run started with --checkpoint-every?)");
  std::string bytes;
  if (!read_whole_file(file, bytes)) {
    const auto status = fs::status(file, ec);
    if (!ec && fs::exists(status) && !fs::is_regular_file(status))
      throw CheckpointError(name +
                            (fs::is_directory(status) ? " is a folder" : " is not a regular file (a pipe, device or socket)") +
                            ", not a checkpoint");
    throw CheckpointError(name + " cannot be read");
  }
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw CheckpointError(name + " is not a framequake checkpoint (wrong magic bytes)");
  if (bytes.size() < kHeaderBytes + kTrailerBytes)
    throw CheckpointError(name + " is truncated (" + std::to_string(bytes.size()) + " bytes, shorter than its header)");
  const auto version = read_pod<std::uint32_t>(bytes, 8);
  const auto marker = read_pod<std::uint32_t>(bytes, 12);
  if (marker != kByteOrderMarker)
    throw CheckpointError(name + " was written on a machine of another byte order (or is damaged)");
  if (version != kCheckpointFormatVersion)
    throw CheckpointError(name + " has format version " + std::to_string(version) + "; this framequake reads version " +
                          std::to_string(kCheckpointFormatVersion));
  const auto length = read_pod<std::uint64_t>(bytes, 16);
  const std::uint64_t expected_size = std::uint64_t(kHeaderBytes) + length + kTrailerBytes;
  if (length > bytes.size() || bytes.size() != expected_size)
    throw CheckpointError(name + " is " + (bytes.size() < expected_size ? "truncated" : "damaged") + ": " +
                          std::to_string(bytes.size()) + " bytes where its header announces " +
                          std::to_string(expected_size));
  std::string payload = bytes.substr(kHeaderBytes, std::size_t(length));
  const auto checksum = read_pod<std::uint64_t>(bytes, kHeaderBytes + std::size_t(length));
  if (checksum != fnv1a(kFnvBasis, payload.data(), payload.size()))
    throw CheckpointError(name + " is damaged (checksum mismatch)");
  return payload;
}

std::vector<CaseFileFingerprint> case_file_fingerprints(const CaseDef& def) {
  std::vector<CaseFileFingerprint> files;
  auto add = [&files](const fs::path& p, const char* what) {
    std::string bytes;
    if (!read_whole_file(p, bytes))
      throw CheckpointError(std::string("cannot read ") + what + " '" + p.string() + "' to check it against the checkpoint");
    const std::uint64_t n = bytes.size();
    const std::uint64_t hash = fnv1a(fnv1a(kFnvBasis, reinterpret_cast<const char*>(&n), sizeof n), bytes.data(), bytes.size());
    // Absolute: a run given a relative case path resolves its records
    // relative to the working folder, a resume reloads the case by its
    // absolute path, and the same file must compare as the same.
    std::error_code ec;
    fs::path file = fs::absolute(p, ec);
    if (ec) file = p;
    files.push_back({what, file.lexically_normal(), hash});
  };
  if (!def.source_file.empty()) add(def.source_file, "case file");
  if (def.ground_motion)
    for (const GroundMotionComponentDef& c : def.ground_motion->components) add(c.resolved_file, "ground-motion record");
  return files;
}

std::string changed_case_files(const std::vector<CaseFileFingerprint>& then,
                               const std::vector<CaseFileFingerprint>& now) {
  // Matched by position (the case file, then the records in the case's
  // order), not by path: a project moved with its files (resume --case)
  // has other paths and the same bytes.
  std::string all;
  auto append = [&all](const std::string& item) { all += (all.empty() ? "" : "; ") + item; };
  const std::size_t n = std::max(then.size(), now.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (k >= then.size()) {
      append("the case now reads the " + now[k].what + " '" + now[k].file.string() + "' as well");
    } else if (k >= now.size()) {
      append("the case no longer reads the " + then[k].what + " '" + then[k].file.string() + "'");
    } else if (then[k].hash != now[k].hash) {
      if (then[k].file == now[k].file)
        append("the " + now[k].what + " '" + now[k].file.string() + "' has changed");
      else
        append("the " + now[k].what + " '" + now[k].file.string() + "' differs from the one the run began with ('" +
               then[k].file.string() + "')");
    }
  }
  return all;
}

}  // namespace fq
