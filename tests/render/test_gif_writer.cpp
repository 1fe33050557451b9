// The GIF writer: palette mapping against a brute-force search, and LZW
// streams decoded by an independent decoder (Pillow) back to the exact input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "render/gif_writer.h"
#include "render_test_util.h"

namespace {

using fq::render::gif_palette_index;
using fq::render::gif_palette_rgb;

int sq(int v) { return v * v; }

TEST(GifPalette, CubeColoursAndGreysMapToThemselves) {
  // The palette is documented as the 6x6x6 cube of multiples of 51 plus 40
  // greys: each of these colours must be reproduced exactly.
  const auto& p = gif_palette_rgb();
  ASSERT_EQ(p.size(), 768u);
  for (int r = 0; r <= 255; r += 51)
    for (int g = 0; g <= 255; g += 51)
      for (int b = 0; b <= 255; b += 51) {
        const int i = gif_palette_index(std::uint8_t(r), std::uint8_t(g), std::uint8_t(b));
        EXPECT_EQ(p[std::size_t(3 * i)], r);
        EXPECT_EQ(p[std::size_t(3 * i + 1)], g);
        EXPECT_EQ(p[std::size_t(3 * i + 2)], b);
      }
  for (int i = 216; i < 256; ++i) {
    const std::uint8_t v = p[std::size_t(3 * i)];
    EXPECT_EQ(p[std::size_t(3 * i + 1)], v);
    EXPECT_EQ(p[std::size_t(3 * i + 2)], v);
    const int j = gif_palette_index(v, v, v);
    EXPECT_EQ(p[std::size_t(3 * j)], v) << "grey " << int(v);
  }
}

TEST(GifPalette, ChoosesTheNearestEntry) {
  // Brute force over all 256 entries is the reference.
  const auto& p = gif_palette_rgb();
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int k = 0; k < 20000; ++k) {
    const int r = byte(rng), g = byte(rng), b = byte(rng);
    int best = 1 << 30;
    for (int i = 0; i < 256; ++i)
      best = std::min(best, sq(r - p[std::size_t(3 * i)]) + sq(g - p[std::size_t(3 * i + 1)]) + sq(b - p[std::size_t(3 * i + 2)]));
    const int c = gif_palette_index(std::uint8_t(r), std::uint8_t(g), std::uint8_t(b));
    const int err = sq(r - p[std::size_t(3 * c)]) + sq(g - p[std::size_t(3 * c + 1)]) + sq(b - p[std::size_t(3 * c + 2)]);
    ASSERT_EQ(err, best) << r << "," << g << "," << b;
  }
}

// Frames of palette colours, so decoding must give back the input exactly.
std::vector<std::uint8_t> palette_frame(int w, int h, int pattern, std::mt19937& rng) {
  const auto& p = gif_palette_rgb();
  std::vector<std::uint8_t> rgb(std::size_t(w) * std::size_t(h) * 3);
  std::uniform_int_distribution<int> entry(0, 255), few(0, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int i = 0;
      switch (pattern) {
        case 0: i = entry(rng); break;                  // noise: table fills and clears often
        case 1: i = 77; break;                          // one colour: long codes, widths up to 12 bits
        case 2: i = (x / 7 + y / 5) % 256; break;       // stripes
        case 3: i = few(rng) * 40; break;               // few colours, random
        default: i = x < pattern - 1000 ? entry(rng) : 5; break;  // >= 1000: noise then one colour
      }
      const std::size_t o = 3 * (std::size_t(y) * std::size_t(w) + std::size_t(x));
      for (int c = 0; c < 3; ++c) rgb[o + std::size_t(c)] = p[std::size_t(3 * i + c)];
    }
  return rgb;
}

void round_trip(int w, int h, const std::vector<int>& patterns, unsigned seed) {
  fq_test::ScratchDir dir;
  std::mt19937 rng(seed);
  const auto gif = dir.path() / "t.gif";
  std::vector<std::vector<std::uint8_t>> frames;
  {
    fq::render::GifWriter writer(gif, w, h, 7);
    for (const int pattern : patterns) {
      frames.push_back(palette_frame(w, h, pattern, rng));
      writer.add_frame(frames.back());
    }
    EXPECT_FALSE(std::filesystem::exists(gif)) << "the animation must appear only when complete";
    writer.finish();
  }
  const fq_test::GifInfo info = fq_test::read_gif_with_pil(gif, dir.path());
  ASSERT_EQ(info.n_frames, int(patterns.size())) << info.json;
  EXPECT_EQ(info.width, w);
  EXPECT_EQ(info.height, h);
  EXPECT_NE(info.json.find("\"loop\": 0"), std::string::npos) << "loops forever: " << info.json;
  EXPECT_NE(info.json.find("70"), std::string::npos) << "7 cs per frame: " << info.json;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06zu.rgb", k);
    const auto decoded = fq_test::read_bytes(dir.path() / name);
    ASSERT_EQ(decoded.size(), frames[k].size()) << "frame " << k;
    EXPECT_TRUE(std::equal(decoded.begin(), decoded.end(), frames[k].begin())) << "frame " << k << " of " << w << "x" << h;
  }
}

TEST(GifWriter, PillowDecodesFramesExactly) {
  if (!fq_test::pil_available()) GTEST_SKIP() << "/usr/bin/python3 with Pillow (python3-pil) is needed";
  round_trip(300, 200, {0, 1, 2, 3}, 1);  // 60000 px: dozens of table clears in the noise frame
  round_trip(640, 480, {1}, 2);           // one colour: the table fills with ever longer runs
  round_trip(1, 1, {0, 0}, 3);
}

TEST(GifWriter, CodeWidthChangesAtTheEndOfTheStream) {
  // Rows of noise then one colour: the number of codes in a frame grows
  // with the noise length, so these frames end just before, at and just
  // after the 9 -> 10 bit switch (table entry 512). Every pixel code must be
  // read back with the right width. (Pillow stops at the last pixel, so the
  // width of the end code itself is not checked here; the encoder follows
  // giflib's rule for it: one bit wider when the last code filled the width.)
  if (!fq_test::pil_available()) GTEST_SKIP() << "/usr/bin/python3 with Pillow (python3-pil) is needed";
  std::vector<int> patterns;
  for (int noise = 230; noise <= 290; ++noise) patterns.push_back(1000 + noise);
  round_trip(320, 1, patterns, 5);
}

TEST(GifWriter, UnfinishedWriterLeavesNothing) {
  fq_test::ScratchDir dir;
  const auto gif = dir.path() / "t.gif";
  {
    fq::render::GifWriter writer(gif, 4, 4, 10);
    writer.add_frame(std::vector<std::uint8_t>(48, 0));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_THROW(fq::render::GifWriter(dir.path() / "missing" / "t.gif", 4, 4, 10), std::runtime_error);
}

}  // namespace
