#include "penumbra/render/image.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <stb_image.h>
#include <stb_image_write.h>

namespace penumbra::render {

void write_png(const std::string& path, const ImageRgba8& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw std::runtime_error("write_png " + path + ": malformed image");
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  if (stbi_write_png(tmp.c_str(), image.width, image.height, 4, image.pixels.data(),
                     image.width * 4) == 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("write_png: cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("write_png: cannot rename " + tmp + " to " + path);
  }
}

ImageRgba8 read_png(const std::string& path) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (data == nullptr) {
    const char* why = stbi_failure_reason();
    throw std::runtime_error("read_png " + path + ": " + (why ? why : "cannot read"));
  }
  ImageRgba8 img;
  img.width = w;
  img.height = h;
  img.pixels.assign(data, data + static_cast<std::size_t>(w) * h * 4);
  stbi_image_free(data);
  return img;
}

ImageComparison compare_images(const ImageRgba8& actual, const ImageRgba8& expected,
                               int tolerance) {
  ImageComparison c;
  c.same_size = actual.width == expected.width && actual.height == expected.height &&
                actual.pixels.size() == expected.pixels.size();
  if (!c.same_size) return c;
  c.pixels = static_cast<std::size_t>(actual.width) * actual.height;
  c.diff = expected;
  for (std::size_t i = 0; i < c.pixels; ++i) {
    int d = 0;
    for (int ch = 0; ch < 3; ++ch)
      d = std::max(d, std::abs(int(actual.pixels[4 * i + ch]) - int(expected.pixels[4 * i + ch])));
    c.max_difference = std::max(c.max_difference, d);
    std::uint8_t* px = &c.diff.pixels[4 * i];
    if (d > tolerance) {
      ++c.differing;
      px[0] = static_cast<std::uint8_t>(std::min(255, 128 + 2 * d));
      px[1] = px[2] = 0;
    } else {
      const int grey = (px[0] + px[1] + px[2]) / 12;
      px[0] = px[1] = px[2] = static_cast<std::uint8_t>(grey);
    }
    px[3] = 255;
  }
  return c;
}

}  // namespace penumbra::render
