// An HDR environment map in memory: equirectangular, linear RGB radiance.
// Direction convention: penumbra/sh/projection.h (equirect_direction): row 0 is the zenith (+z).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra::data {

struct EnvironmentMap {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;          // width * height * 3 floats, row-major, row 0 = zenith
  std::string source;              // file it was loaded from, for messages
  std::size_t clamped_values = 0;  // negative values the loader removed (exr.h)

  const float* texel(int x, int y) const {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
  }
};

}  // namespace penumbra::data
