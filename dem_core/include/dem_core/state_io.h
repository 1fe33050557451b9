// Binary writer and reader of a simulation's state, for checkpoints.
//
// Why a hand-made format: a checkpoint must give back the state bit for bit
// (a resumed run is bitwise identical to an uninterrupted one), so doubles
// are copied as their 8 bytes, never printed. Each owner of state (the
// simulation, each force provider) writes its own members in a fixed order
// and reads them back in the same order; dem_core thus stays ignorant of
// joints and contacts, and io only frames the bytes (magic, version,
// checksum; io/checkpoint.h).
//
// Byte order is the machine's own; the file header (io/checkpoint.h) holds
// a marker so a file from a machine of the other order is refused rather
// than misread.
//
// Every read is bounds-checked: a truncated or damaged stream throws
// StateFormatError saying what was being read, never reads past the end and
// never allocates more than the bytes left could describe.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "dem_core/types.h"

namespace fq {

// The state stream does not match what the reader expects (truncated,
// damaged, or written for another scene).
class StateFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StateWriter {
 public:
  // A named section marker: the reader checks it, so a reader that got out
  // of step with the writer says where.
  void section(std::string_view name) {
    u32(0x5EC7104Eu);
    str(name);
  }
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.append(p, sizeof(T));
  }
  void u8(std::uint8_t v) { pod(v); }
  void u32(std::uint32_t v) { pod(v); }
  void u64(std::uint64_t v) { pod(v); }
  void i64(std::int64_t v) { pod(v); }
  void f64(double v) { pod(v); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void vec3(const Vec3& v) { bytes_.append(reinterpret_cast<const char*>(v.data()), 3 * sizeof(double)); }
  void quat(const Quat& q) { bytes_.append(reinterpret_cast<const char*>(q.coeffs().data()), 4 * sizeof(double)); }
  void mat3(const Mat3& m) { bytes_.append(reinterpret_cast<const char*>(m.data()), 9 * sizeof(double)); }
  void str(std::string_view s) {
    u64(s.size());
    bytes_.append(s.data(), s.size());
  }
  // A vector of plain values: its length, then its bytes.
  template <class T>
  void vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    u64(v.size());
    if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void vec3s(const std::vector<Vec3>& v) {
    u64(v.size());
    for (const Vec3& x : v) vec3(x);
  }
  void quats(const std::vector<Quat>& v) {
    u64(v.size());
    for (const Quat& x : v) quat(x);
  }
  void mat3s(const std::vector<Mat3>& v) {
    u64(v.size());
    for (const Mat3& x : v) mat3(x);
  }

  const std::string& bytes() const { return bytes_; }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  explicit StateReader(std::string_view bytes) : bytes_(bytes) {}

  // Reads a section marker; throws unless it is `name`.
  void section(std::string_view name) {
    const std::string what = std::string("section '") + std::string(name) + "'";
    if (u32(what.c_str()) != 0x5EC7104Eu) fail("section marker of '" + std::string(name) + "' not found");
    const std::string got = str(what.c_str());
    if (got != name) fail("expected section '" + std::string(name) + "', found '" + got.substr(0, 40) + "'");
  }
  template <class T>
  T pod(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint8_t u8(const char* what) { return pod<std::uint8_t>(what); }
  std::uint32_t u32(const char* what) { return pod<std::uint32_t>(what); }
  std::uint64_t u64(const char* what) { return pod<std::uint64_t>(what); }
  std::int64_t i64(const char* what) { return pod<std::int64_t>(what); }
  double f64(const char* what) { return pod<double>(what); }
  bool boolean(const char* what) {
    const std::uint8_t v = u8(what);
    if (v > 1) fail(std::string(what) + ": not a boolean");
    return v == 1;
  }
  Vec3 vec3(const char* what) {
    Vec3 v;
    raw(v.data(), 3 * sizeof(double), what);
    return v;
  }
  Quat quat(const char* what) {
    Quat q;
    raw(q.coeffs().data(), 4 * sizeof(double), what);
    return q;
  }
  Mat3 mat3(const char* what) {
    Mat3 m;
    raw(m.data(), 9 * sizeof(double), what);
    return m;
  }
  std::string str(const char* what) {
    const std::uint64_t n = u64(what);
    need_count(n, 1, what);
    std::string s(bytes_.substr(pos_, std::size_t(n)));
    pos_ += std::size_t(n);
    return s;
  }
  // Reads a vector of plain values; when `expected_size` is given (not
  // npos) its length must be exactly that.
  template <class T>
  std::vector<T> vec(const char* what, std::size_t expected_size = npos) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::uint64_t n = count(what, expected_size, sizeof(T));
    std::vector<T> v(static_cast<std::size_t>(n));
    if (n) raw(v.data(), std::size_t(n) * sizeof(T), what);
    return v;
  }
  std::vector<Vec3> vec3s(const char* what, std::size_t expected_size = npos) {
    const std::uint64_t n = count(what, expected_size, 3 * sizeof(double));
    std::vector<Vec3> v(static_cast<std::size_t>(n));
    for (Vec3& x : v) x = vec3(what);
    return v;
  }
  std::vector<Quat> quats(const char* what, std::size_t expected_size = npos) {
    const std::uint64_t n = count(what, expected_size, 4 * sizeof(double));
    std::vector<Quat> v(static_cast<std::size_t>(n));
    for (Quat& x : v) x = quat(what);
    return v;
  }
  std::vector<Mat3> mat3s(const char* what, std::size_t expected_size = npos) {
    const std::uint64_t n = count(what, expected_size, 9 * sizeof(double));
    std::vector<Mat3> v(static_cast<std::size_t>(n));
    for (Mat3& x : v) x = mat3(what);
    return v;
  }

  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::size_t position() const { return pos_; }
  [[noreturn]] void fail(const std::string& message) const {
    throw StateFormatError(message + " (at byte " + std::to_string(pos_) + ")");
  }

  static constexpr std::size_t npos = std::size_t(-1);

 private:
  void need(std::size_t n, const char* what) const {
    if (n > remaining()) fail(std::string("truncated while reading ") + what);
  }
  void need_count(std::uint64_t n, std::size_t item_bytes, const char* what) const {
    if (n > remaining() / item_bytes) fail(std::string("truncated or damaged length of ") + what);
  }
  std::uint64_t count(const char* what, std::size_t expected_size, std::size_t item_bytes) {
    const std::uint64_t n = u64(what);
    if (expected_size != npos && n != expected_size)
      fail(std::string(what) + ": " + std::to_string(n) + " entries, this scene has " +
           std::to_string(expected_size));
    need_count(n, item_bytes, what);
    return n;
  }
  void raw(void* out, std::size_t n, const char* what) {
    need(n, what);
    std::memcpy(out, bytes_.data() + pos_, n);
    pos_ += n;
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
};

}  // namespace fq
