#include "render/gif_writer.h"

#include <array>
#include <cstdlib>
#include <stdexcept>
#include <system_error>

namespace fq::render {

namespace {

constexpr int kCubeLevels = 6;
constexpr int kCubeStep = 51;  // 255 / (kCubeLevels - 1)
constexpr int kGreysPerStep = 8;

std::vector<std::uint8_t> make_palette() {
  std::vector<std::uint8_t> p;
  p.reserve(256 * 3);
  for (int r = 0; r < kCubeLevels; ++r)
    for (int g = 0; g < kCubeLevels; ++g)
      for (int b = 0; b < kCubeLevels; ++b) {
        p.push_back(std::uint8_t(r * kCubeStep));
        p.push_back(std::uint8_t(g * kCubeStep));
        p.push_back(std::uint8_t(b * kCubeStep));
      }
  // Greys between the cube's grey steps: renderings are full of shaded
  // neutral tones (ground, text, edges) that the cube alone would band.
  for (int step = 0; step < kCubeLevels - 1; ++step)
    for (int j = 1; j <= kGreysPerStep; ++j) {
      const auto v = std::uint8_t(step * kCubeStep + (j * kCubeStep + (kGreysPerStep + 1) / 2) / (kGreysPerStep + 1));
      p.insert(p.end(), {v, v, v});
    }
  return p;
}

// Nearest grey entry (cube greys included) for each channel sum r + g + b
// (0..765): the grey g minimising (r-g)^2 + (g-g)^2 + (b-g)^2 is the one
// closest to the mean, i.e. minimising |3 g - sum| (exact, no rounding).
std::array<std::uint8_t, 766> make_grey_table(const std::vector<std::uint8_t>& palette) {
  std::array<std::uint8_t, 766> table{};
  for (int sum = 0; sum <= 765; ++sum) {
    int best = 0, best_err = 1 << 30;
    for (int i = 0; i < 256; ++i) {
      const int r = palette[std::size_t(3 * i)], g = palette[std::size_t(3 * i + 1)], b = palette[std::size_t(3 * i + 2)];
      if (r != g || g != b) continue;
      const int err = std::abs(3 * r - sum);
      if (err < best_err) best_err = err, best = i;
    }
    table[std::size_t(sum)] = std::uint8_t(best);
  }
  return table;
}

int sq(int v) { return v * v; }

// Bit sink of the LZW stream: codes packed least significant bit first.
class BitPacker {
 public:
  void put(int code, int width) {
    acc_ |= std::uint32_t(code) << bits_;
    bits_ += width;
    while (bits_ >= 8) {
      bytes_.push_back(std::uint8_t(acc_ & 0xffu));
      acc_ >>= 8;
      bits_ -= 8;
    }
  }
  std::vector<std::uint8_t> finish() {
    if (bits_ > 0) bytes_.push_back(std::uint8_t(acc_ & 0xffu));
    return std::move(bytes_);
  }

 private:
  std::uint32_t acc_ = 0;
  int bits_ = 0;
  std::vector<std::uint8_t> bytes_;
};

void put_u16(std::ofstream& out, int v) {
  const char b[2] = {char(v & 0xff), char((v >> 8) & 0xff)};
  out.write(b, 2);
}

}  // namespace

const std::vector<std::uint8_t>& gif_palette_rgb() {
  static const std::vector<std::uint8_t> palette = make_palette();
  return palette;
}

std::uint8_t gif_palette_index(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  static const std::array<std::uint8_t, 766> grey = make_grey_table(gif_palette_rgb());
  const std::vector<std::uint8_t>& p = gif_palette_rgb();
  // Nearest cube entry: each channel rounded to its nearest level.
  const int ri = (r + kCubeStep / 2) / kCubeStep, gi = (g + kCubeStep / 2) / kCubeStep, bi = (b + kCubeStep / 2) / kCubeStep;
  const int cube = ri * 36 + gi * 6 + bi;
  const int cube_err = sq(r - ri * kCubeStep) + sq(g - gi * kCubeStep) + sq(b - bi * kCubeStep);
  // Nearest grey: the grey closest to the channel mean minimises the squared error.
  const std::uint8_t gidx = grey[std::size_t(r + g + b)];
  const int gv = p[std::size_t(3 * gidx)];
  const int grey_err = sq(r - gv) + sq(g - gv) + sq(b - gv);
  return grey_err < cube_err ? gidx : std::uint8_t(cube);
}

std::vector<std::uint8_t> gif_lzw_encode(std::span<const std::uint8_t> indices) {
  constexpr int kMinCodeSize = 8;
  constexpr int kClear = 1 << kMinCodeSize, kEnd = kClear + 1, kFirstFree = kClear + 2;
  constexpr int kMaxCodes = 4096;  // 12-bit codes
  // Dictionary: child code of (prefix code, next index). Entries carry the
  // epoch of the table they belong to, so a clear code costs no memset.
  struct Entry {
    std::uint16_t epoch = 0;
    std::uint16_t code = 0;
  };
  thread_local std::vector<Entry> table;
  thread_local std::uint16_t epoch = 0;
  if (table.empty()) table.resize(std::size_t(kMaxCodes) * 256);
  auto reset_table = [&] {
    if (++epoch == 0) {  // wrapped: old stamps could alias, clear for real
      std::fill(table.begin(), table.end(), Entry{});
      epoch = 1;
    }
  };

  BitPacker bits;
  int width = kMinCodeSize + 1;
  int next = kFirstFree;
  reset_table();
  bits.put(kClear, width);
  if (!indices.empty()) {
    int prefix = indices[0];
    for (std::size_t i = 1; i < indices.size(); ++i) {
      const std::uint8_t k = indices[i];
      Entry& e = table[std::size_t(prefix) * 256 + k];
      if (e.epoch == epoch) {
        prefix = e.code;
        continue;
      }
      bits.put(prefix, width);
      if (next == kMaxCodes) {
        // Table full: start again. The decoder, one entry behind, is also
        // at 12-bit codes here, so the clear code is read with this width.
        bits.put(kClear, width);
        reset_table();
        width = kMinCodeSize + 1;
        next = kFirstFree;
      } else {
        e.epoch = epoch;
        e.code = std::uint16_t(next++);
        if (next > (1 << width) && width < 12) ++width;
      }
      prefix = k;
    }
    bits.put(prefix, width);
    // The decoder adds one more entry on reading that last code; if that
    // fills the current width it reads the end code one bit wider.
    if (next == (1 << width) && width < 12) ++width;
  }
  bits.put(kEnd, width);
  const std::vector<std::uint8_t> packed = bits.finish();

  std::vector<std::uint8_t> out;
  out.reserve(packed.size() + packed.size() / 255 + 3);
  out.push_back(std::uint8_t(kMinCodeSize));
  for (std::size_t pos = 0; pos < packed.size(); pos += 255) {
    const std::size_t n = std::min<std::size_t>(255, packed.size() - pos);
    out.push_back(std::uint8_t(n));
    out.insert(out.end(), packed.begin() + std::ptrdiff_t(pos), packed.begin() + std::ptrdiff_t(pos + n));
  }
  out.push_back(0);
  return out;
}

GifWriter::GifWriter(std::filesystem::path file, int width, int height, int delay_cs)
    : file_(std::move(file)), width_(width), height_(height), delay_cs_(delay_cs) {
  if (width < 1 || width > 65535 || height < 1 || height > 65535)
    throw std::invalid_argument("GIF size must be 1..65535 pixels per side");
  if (delay_cs < 0 || delay_cs > 65535) throw std::invalid_argument("GIF frame delay must be 0..65535 cs");
  temp_ = file_;
  temp_ += ".part";
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot open '" + temp_.string() + "' for writing");
  out_.write("GIF89a", 6);
  put_u16(out_, width_);
  put_u16(out_, height_);
  // Global colour table of 2^(7+1) entries, 8 bits per primary.
  const char screen[3] = {char(0xF7), 0, 0};
  out_.write(screen, 3);
  const std::vector<std::uint8_t>& pal = gif_palette_rgb();
  out_.write(reinterpret_cast<const char*>(pal.data()), std::streamsize(pal.size()));
  // Application extension NETSCAPE2.0: loop count 0 = forever.
  const char loop[19] = {0x21, char(0xFF), 0x0B, 'N', 'E', 'T', 'S', 'C', 'A', 'P', 'E', '2', '.', '0', 0x03, 0x01, 0, 0, 0};
  out_.write(loop, sizeof loop);
  check_stream_("writing the GIF header");
}

GifWriter::~GifWriter() {
  if (!finished_) {
    out_.close();
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void GifWriter::check_stream_(const char* what) {
  if (!out_) throw std::runtime_error(std::string("I/O error ") + what + " of '" + temp_.string() + "'");
}

void GifWriter::add_frame(std::span<const std::uint8_t> rgb) {
  const std::size_t n = std::size_t(width_) * std::size_t(height_);
  if (rgb.size() != 3 * n) throw std::invalid_argument("GIF frame has the wrong number of bytes");
  indices_.resize(n);
  for (std::size_t i = 0; i < n; ++i) indices_[i] = gif_palette_index(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
  // Graphic control extension: no disposal specified, no transparency.
  const char gce[4] = {0x21, char(0xF9), 0x04, 0x00};
  out_.write(gce, 4);
  put_u16(out_, delay_cs_);
  const char gce_end[2] = {0, 0};
  out_.write(gce_end, 2);
  // Image descriptor: whole screen, global palette, not interlaced.
  out_.put(0x2C);
  put_u16(out_, 0);
  put_u16(out_, 0);
  put_u16(out_, width_);
  put_u16(out_, height_);
  out_.put(0);
  const std::vector<std::uint8_t> data = gif_lzw_encode(indices_);
  out_.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
  check_stream_("writing a frame");
  ++frames_;
}

void GifWriter::finish() {
  out_.put(0x3B);
  out_.close();
  if (!out_) throw std::runtime_error("I/O error closing '" + temp_.string() + "'");
  std::error_code ec;
  std::filesystem::rename(temp_, file_, ec);
  if (ec) throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + file_.string() + "': " + ec.message());
  finished_ = true;
}

}  // namespace fq::render
