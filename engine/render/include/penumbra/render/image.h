// 8-bit RGBA images on the CPU: screenshots (PNG, written atomically), golden-image
// comparison and diff images.
//
// Threading: plain functions over values; thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::render {

struct ImageRgba8 {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 4, row-major, top row first
};

// Writes a PNG atomically: to a temporary file in the same folder, then rename(), so readers
// never see a partial file. Throws std::runtime_error naming the path on failure.
void write_png(const std::string& path, const ImageRgba8& image);
// Throws std::runtime_error naming the path when the file is missing or not an image.
ImageRgba8 read_png(const std::string& path);

struct ImageComparison {
  bool same_size = false;
  std::size_t pixels = 0;
  std::size_t differing = 0;  // pixels with some channel (RGB) differing by more than tolerance
  int max_difference = 0;     // largest channel difference over all pixels
  double fraction() const { return pixels ? static_cast<double>(differing) / pixels : 1.0; }
  // Visualisation: differing pixels red (brighter = larger), others a dimmed grey of expected.
  ImageRgba8 diff;
};

// Compares RGB channels (alpha ignored); `tolerance` in 8-bit steps.
ImageComparison compare_images(const ImageRgba8& actual, const ImageRgba8& expected, int tolerance);

}  // namespace penumbra::render
