#include "penumbra/render/lighting_texels.h"

#include <algorithm>
#include <cmath>

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::render {
namespace {

bool usable(float v) {
  return std::isfinite(v) && v >= 0.0f;
}
bool usable(const glm::vec3& c) {
  return usable(c.x) && usable(c.y) && usable(c.z);
}

std::uint8_t unorm8(float v) {  // v in [0, 1]; an explicit multiply-add, as the AVX2 path
  return static_cast<std::uint8_t>(std::min(255.0f, std::fma(v, 255.0f, 0.5f)));
}

// One texel (the AVX2 path's tail and the build without AVX2).
void pack_one(const glm::vec3& c, float scale, float inv_scale, std::uint8_t* t,
              std::size_t& rejected) {
  const float m = std::max({c.x, c.y, c.z});
  if (!usable(c) || !(m > 0.0f)) {
    rejected += usable(c) ? 0 : 1;
    t[0] = t[1] = t[2] = t[3] = 0;
    return;
  }
  const float a = std::min(255.0f, std::ceil(m * inv_scale * 255.0f));  // >= 1: m > 0
  const float to_unit = 255.0f / (a * scale);                           // c / (a / 255 * scale)
  t[0] = unorm8(std::min(1.0f, c.x * to_unit));
  t[1] = unorm8(std::min(1.0f, c.y * to_unit));
  t[2] = unorm8(std::min(1.0f, c.z * to_unit));
  t[3] = static_cast<std::uint8_t>(a);
}

#ifdef __AVX2__
// Texels i .. i + 7 as three vectors of x, y, z.
void load8(const glm::vec3* rgb, std::size_t i, __m256& x, __m256& y, __m256& z) {
  const float* f = &rgb[i].x;
  const __m256i idx = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
  x = _mm256_i32gather_ps(f, idx, 4);
  y = _mm256_i32gather_ps(f + 1, idx, 4);
  z = _mm256_i32gather_ps(f + 2, idx, 4);
}
// Finite and >= 0 on every channel.
__m256 usable8(__m256 x, __m256 y, __m256 z) {
  const __m256 zero = _mm256_setzero_ps(), inf = _mm256_set1_ps(INFINITY);
  auto ok = [&](__m256 v) {
    return _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ), _mm256_cmp_ps(v, inf, _CMP_LT_OQ));
  };
  return _mm256_and_ps(ok(x), _mm256_and_ps(ok(y), ok(z)));
}
#endif

}  // namespace

RgbmPacking pack_rgbm(const glm::vec3* rgb, std::size_t n, std::uint8_t* out) {
  RgbmPacking p;
  float largest = 0.0f;
  std::size_t i = 0;
#ifdef __AVX2__
  // Eight texels a step, the same operations as pack_one (so the same bytes: tested).
  __m256 top = _mm256_setzero_ps();
  for (; i + 8 <= n; i += 8) {
    __m256 x, y, z;
    load8(rgb, i, x, y, z);
    const __m256 m = _mm256_max_ps(x, _mm256_max_ps(y, z));
    top = _mm256_max_ps(top, _mm256_and_ps(usable8(x, y, z), m));
  }
  alignas(32) float lanes[8];
  _mm256_store_ps(lanes, top);
  for (const float v : lanes) largest = std::max(largest, v);
#endif
  for (; i < n; ++i)
    if (usable(rgb[i])) largest = std::max({largest, rgb[i].x, rgb[i].y, rgb[i].z});
  if (largest > 0.0f) p.scale = largest;
  const float inv_scale = 1.0f / p.scale;
  i = 0;
#ifdef __AVX2__
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 c255 = _mm256_set1_ps(255.0f), half = _mm256_set1_ps(0.5f);
  const __m256 vscale = _mm256_set1_ps(p.scale), vinv = _mm256_set1_ps(inv_scale);
  for (; i + 8 <= n; i += 8) {
    __m256 x, y, z;
    load8(rgb, i, x, y, z);
    const __m256 ok = usable8(x, y, z);
    const __m256 m = _mm256_max_ps(x, _mm256_max_ps(y, z));
    const __m256 good = _mm256_and_ps(ok, _mm256_cmp_ps(m, zero, _CMP_GT_OQ));
    p.rejected += static_cast<std::size_t>(8 - __builtin_popcount(_mm256_movemask_ps(ok)));
    const __m256 a =
        _mm256_min_ps(c255, _mm256_ceil_ps(_mm256_mul_ps(_mm256_mul_ps(m, vinv), c255)));
    const __m256 to_unit = _mm256_div_ps(c255, _mm256_mul_ps(a, vscale));
    auto unorm = [&](__m256 c) {
      const __m256 v = _mm256_min_ps(one, _mm256_mul_ps(c, to_unit));
      return _mm256_cvttps_epi32(_mm256_min_ps(c255, _mm256_fmadd_ps(v, c255, half)));
    };
    __m256i texel = _mm256_or_si256(_mm256_or_si256(unorm(x), _mm256_slli_epi32(unorm(y), 8)),
                                    _mm256_or_si256(_mm256_slli_epi32(unorm(z), 16),
                                                    _mm256_slli_epi32(_mm256_cvttps_epi32(a), 24)));
    texel = _mm256_and_si256(texel, _mm256_castps_si256(good));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 4 * i), texel);
  }
#endif
  for (; i < n; ++i) pack_one(rgb[i], p.scale, inv_scale, out + 4 * i, p.rejected);
  return p;
}

RgbmPacking pack_rgbm_scalar(const glm::vec3* rgb, std::size_t n, std::uint8_t* out) {
  RgbmPacking p;
  float largest = 0.0f;
  for (std::size_t i = 0; i < n; ++i)
    if (usable(rgb[i])) largest = std::max({largest, rgb[i].x, rgb[i].y, rgb[i].z});
  if (largest > 0.0f) p.scale = largest;
  const float inv_scale = 1.0f / p.scale;
  for (std::size_t i = 0; i < n; ++i) pack_one(rgb[i], p.scale, inv_scale, out + 4 * i, p.rejected);
  return p;
}

glm::vec3 unpack_rgbm(const std::uint8_t* texel, float scale) {
  const float a = texel[3] / 255.0f;
  return glm::vec3(texel[0], texel[1], texel[2]) / 255.0f * a * scale;
}

}  // namespace penumbra::render
