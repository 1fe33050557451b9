// Animated GIF (GIF89a) writer with a fixed 256-colour palette and LZW
// compression, written for framequake so that animations need nothing beyond
// VTK (Debian 12's VTK has no FFMPEG writer).
//
// Palette: a 6 x 6 x 6 colour cube (channel levels 0, 51, ..., 255) followed
// by 40 greys between the cube's grey steps. Every pixel maps to the nearest
// palette entry (no dithering: flat colours of the renderer, such as the
// damage colours, stay flat and the animation compresses well). Colours
// whose channels are multiples of 51 are reproduced exactly.
//
// The file is written under a temporary name next to the target and renamed
// by finish(), so the target exists only when complete.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace fq::render {

// The fixed palette: 256 entries of r, g, b.
const std::vector<std::uint8_t>& gif_palette_rgb();
// Index of the palette entry nearest to (r, g, b).
std::uint8_t gif_palette_index(std::uint8_t r, std::uint8_t g, std::uint8_t b);

// LZW-compresses palette indices as the GIF image data stream (minimum code
// size 8, variable code width up to 12 bits, clear code when the table is
// full), packed into sub-blocks with the terminating zero block.
std::vector<std::uint8_t> gif_lzw_encode(std::span<const std::uint8_t> indices);

class GifWriter {
 public:
  // Opens `file`'s temporary sibling. width, height in pixels (1..65535);
  // delay between frames in hundredths of a second; the animation loops
  // forever. Throws std::runtime_error naming the file if it cannot be opened.
  GifWriter(std::filesystem::path file, int width, int height, int delay_cs);
  ~GifWriter();  // removes the temporary file if finish() was not called
  GifWriter(const GifWriter&) = delete;
  GifWriter& operator=(const GifWriter&) = delete;

  // One frame, rows from top to bottom, r g b bytes per pixel.
  void add_frame(std::span<const std::uint8_t> rgb);
  // Writes the trailer, closes and renames to the target. Throws on I/O error.
  void finish();
  int frames() const { return frames_; }

 private:
  void check_stream_(const char* what);
  std::filesystem::path file_, temp_;
  std::ofstream out_;
  int width_, height_, delay_cs_;
  int frames_ = 0;
  bool finished_ = false;
  std::vector<std::uint8_t> indices_;  // reused per frame
};

}  // namespace fq::render
