#include "penumbra/render/lighting_texels.h"

#include <algorithm>
#include <cmath>

namespace penumbra::render {
namespace {

bool usable(float v) {
  return std::isfinite(v) && v >= 0.0f;
}
bool usable(const glm::vec3& c) {
  return usable(c.x) && usable(c.y) && usable(c.z);
}

std::uint8_t unorm8(float v) {  // v in [0, 1]
  return static_cast<std::uint8_t>(std::min(255.0f, v * 255.0f + 0.5f));
}

}  // namespace

RgbmPacking pack_rgbm(const glm::vec3* rgb, std::size_t n, std::uint8_t* out) {
  RgbmPacking p;
  float largest = 0.0f;
  for (std::size_t i = 0; i < n; ++i)
    if (usable(rgb[i])) largest = std::max({largest, rgb[i].x, rgb[i].y, rgb[i].z});
  if (largest > 0.0f) p.scale = largest;
  const float inv_scale = 1.0f / p.scale;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t* t = out + 4 * i;
    const glm::vec3 c = rgb[i];
    const float m = std::max({c.x, c.y, c.z});
    if (!usable(c) || !(m > 0.0f)) {
      p.rejected += usable(c) ? 0 : 1;
      t[0] = t[1] = t[2] = t[3] = 0;
      continue;
    }
    const float a = std::min(255.0f, std::ceil(m * inv_scale * 255.0f));  // >= 1: m > 0
    const float to_unit = 255.0f / (a * p.scale);                         // c / (a / 255 * scale)
    t[0] = unorm8(std::min(1.0f, c.x * to_unit));
    t[1] = unorm8(std::min(1.0f, c.y * to_unit));
    t[2] = unorm8(std::min(1.0f, c.z * to_unit));
    t[3] = static_cast<std::uint8_t>(a);
  }
  return p;
}

glm::vec3 unpack_rgbm(const std::uint8_t* texel, float scale) {
  const float a = texel[3] / 255.0f;
  return glm::vec3(texel[0], texel[1], texel[2]) / 255.0f * a * scale;
}

}  // namespace penumbra::render
