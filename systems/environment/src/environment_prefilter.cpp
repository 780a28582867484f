#include "penumbra/systems/environment/environment_prefilter.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace penumbra::environment {

namespace {

std::string map_name(const data::EnvironmentMap& map) {
  return map.source.empty() ? std::string("environment map") : map.source;
}

}  // namespace

void check_environment_map(const data::EnvironmentMap& map) {
  if (map.width <= 0 || map.height <= 0) {
    throw std::invalid_argument(map_name(map) + ": size " + std::to_string(map.width) + "x" +
                                std::to_string(map.height) + " is not positive");
  }
  const std::size_t expected = static_cast<std::size_t>(map.width) * map.height * 3;
  if (map.rgb.size() != expected) {
    throw std::invalid_argument(map_name(map) + ": " + std::to_string(map.rgb.size()) +
                                " floats for a " + std::to_string(map.width) + "x" +
                                std::to_string(map.height) + " RGB map (expected " +
                                std::to_string(expected) + ")");
  }
  for (std::size_t i = 0; i < expected; ++i) {
    const float v = map.rgb[i];
    if (std::isfinite(v) && v >= 0.0f) continue;
    const std::size_t t = i / 3;
    const char* what = std::isnan(v) ? "NaN" : (std::isinf(v) ? "infinite" : "negative");
    throw std::invalid_argument(map_name(map) + ": texel (" + std::to_string(t % map.width) + ", " +
                                std::to_string(t / map.width) + ") channel " + "RGB"[i % 3] +
                                " is " + what + " (" + std::to_string(v) +
                                "); light-source detection rejects it rather than clamping");
  }
}

std::vector<float> luminance_image(const data::EnvironmentMap& map) {
  const std::size_t n = static_cast<std::size_t>(map.width) * map.height;
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = luminance(map.rgb.data() + 3 * i);  // eq. 3.1
  return out;
}

std::vector<float> gaussian_prefilter(const std::vector<float>& image, int width, int height,
                                      int radius) {
  if (width <= 0 || height <= 0 ||
      image.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw std::invalid_argument("gaussian_prefilter: image of " + std::to_string(image.size()) +
                                " values does not match the size " + std::to_string(width) + "x" +
                                std::to_string(height));
  }
  if (radius < 0 || 2 * radius >= width) {
    throw std::invalid_argument("gaussian_prefilter: radius " + std::to_string(radius) +
                                " must be in [0, width/2) for a map " + std::to_string(width) +
                                " texels wide");
  }
  if (radius == 0) return image;
  // [Ambrosj16] sec. 5.1.1: Gaussian blur, default radius 4 (sigma = radius / 2 here).
  const float sigma = 0.5f * static_cast<float>(radius);
  std::vector<float> kernel(static_cast<std::size_t>(2 * radius + 1));
  float sum = 0;
  for (int k = -radius; k <= radius; ++k) {
    const float w = std::exp(-0.5f * static_cast<float>(k * k) / (sigma * sigma));
    kernel[static_cast<std::size_t>(k + radius)] = w;
    sum += w;
  }
  for (float& w : kernel) w /= sum;

  std::vector<float> rows(image.size());
  for (int y = 0; y < height; ++y) {
    const float* in = image.data() + static_cast<std::size_t>(y) * width;
    float* out = rows.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      float acc = 0;
      for (int k = -radius; k <= radius; ++k) {
        int xx = x + k;  // wraps around the longitude seam
        if (xx < 0) xx += width;
        if (xx >= width) xx -= width;
        acc += kernel[static_cast<std::size_t>(k + radius)] * in[xx];
      }
      out[x] = acc;
    }
  }
  std::vector<float> out(image.size());
  for (int y = 0; y < height; ++y) {
    float* dst = out.data() + static_cast<std::size_t>(y) * width;
    for (int k = -radius; k <= radius; ++k) {
      const int yy = y + k < 0 ? 0 : (y + k >= height ? height - 1 : y + k);  // clamps at poles
      const float w = kernel[static_cast<std::size_t>(k + radius)];
      const float* src = rows.data() + static_cast<std::size_t>(yy) * width;
      for (int x = 0; x < width; ++x) dst[x] += w * src[x];
    }
  }
  return out;
}

}  // namespace penumbra::environment
