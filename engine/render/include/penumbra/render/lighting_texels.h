// Lighting texels: the terrain's per-texel radiance (RGB floats, unbounded) packed as RGBM in
// RGBA8 for the terrain pass's lighting texture. On lavapipe a bilinear fetch from an 8-bit
// UNORM texture takes llvmpipe's fixed-point path, about 1.2 ms a frame cheaper for the main job
// than RGBA16F (docs/play.md, section 1); the shader decodes rgb * a * scale.
//
// Encoding (the RGBM of lightmaps): scale = the largest channel over all texels; per texel
// a = ceil(255 max(r, g, b) / scale) / 255 (the texel's own range, so dark texels keep their
// relative precision), rgb = round(255 c / (a scale)) / 255. Each decoded channel is within
// a scale / 510 <= max(c) / 510 + scale / 130050 of the input: 0.2% of the texel's largest
// channel plus 1/130050 of the terrain's brightest. Bilinear filtering mixes rgb and a
// separately; the largest channel stays near 1, so what filtering changes is the chroma
// between texels of different colours, not brightness.
//
// Bad input: NaN, infinite or negative channels encode as 0 (black), counted in the result;
// all-black or empty input gives scale 1.
//
// Threading: pure functions.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

namespace penumbra::render {

struct RgbmPacking {
  float scale = 1.0f;        // decode: rgb * a * scale
  std::size_t rejected = 0;  // texels with a NaN, infinite or negative channel (set to 0)
};

// Packs n texels into out[4 n] (RGBA8 UNORM order); eight texels a step with AVX2.
RgbmPacking pack_rgbm(const glm::vec3* rgb, std::size_t n, std::uint8_t* out);
// The same one texel at a time (tests: both give the same bytes).
RgbmPacking pack_rgbm_scalar(const glm::vec3* rgb, std::size_t n, std::uint8_t* out);

// The value the shader reconstructs from one packed texel (tests, tools).
glm::vec3 unpack_rgbm(const std::uint8_t* texel, float scale);

}  // namespace penumbra::render
