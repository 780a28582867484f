// The first steps of light-source detection ([Ambrosj16] sec. 4.1, 5.1.1) on an equirectangular
// HDR map: the input check, per-texel luminance (eq. 3.1) and the Gaussian prefilter.
//
// Contract: maps follow penumbra/data/environment_map.h (row 0 = zenith, u = azimuth from +x
// towards +y, linear RGB). check_environment_map throws std::invalid_argument naming the map
// (EnvironmentMap::source, or "environment map" when empty), the texel and the reason on a
// non-positive size, a pixel buffer of the wrong length, or a NaN, infinite or negative value:
// such texels are rejected, never clamped (the EXR loader already rejects NaN/inf naming the
// file and removes DWA's negative ringing, assets/exr.h). The other functions expect a checked
// map. Threading: pure functions of their arguments; independent calls may run concurrently.
#pragma once

#include <vector>

#include "penumbra/data/environment_map.h"

namespace penumbra::environment {

// Throws std::invalid_argument as described above; returns normally for a valid map.
void check_environment_map(const data::EnvironmentMap& map);

// Luminance of a linear RGB radiance value ([Ambrosj16] eq. 3.1): 179 (0.265 R + 0.670 G +
// 0.065 B), in cd/m^2 for Radiance-format primaries.
inline float luminance(const float* rgb) {
  return 179.0f * (0.265f * rgb[0] + 0.670f * rgb[1] + 0.065f * rgb[2]);
}

// width * height luminances of the map, row-major (eq. 3.1).
std::vector<float> luminance_image(const data::EnvironmentMap& map);

// Separable Gaussian blur of a width x height single-channel image with a kernel truncated at
// `radius` texels (sigma = radius / 2; radius 0 returns the input). Rows wrap around the
// longitude seam (column -1 is column width-1); columns clamp at the poles. The kernel is
// normalised, so a constant image is unchanged. Throws std::invalid_argument on a negative
// radius, a radius of half the width or more, or a size that does not match `image`.
std::vector<float> gaussian_prefilter(const std::vector<float>& image, int width, int height,
                                      int radius);

}  // namespace penumbra::environment
