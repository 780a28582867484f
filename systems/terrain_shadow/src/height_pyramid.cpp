// Height pyramid ([Meier13] sec. 4.2.1, 5.1): per level a separable tent
// decimation to spacing s = sr^i and a cubic B-spline reconstruction back to full resolution.
// Every level is filtered from level 0 directly (not from the previous level), so its kernel
// depends on s only, not on level_step. Rows are processed whole, so the y passes (most of the
// work) are contiguous multiply-adds over x that the compiler vectorises.
#include "penumbra/systems/terrain_shadow/height_pyramid.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {
namespace {

constexpr int kMaxLevelStep = 16;

// Uniform cubic B-spline basis at t in [0, 1) ([Meier13] eq. 4.9-4.12).
void bspline_weights(float t, float w[4]) {
  const float t2 = t * t, t3 = t2 * t;
  w[0] = (1 - t) * (1 - t) * (1 - t) / 6;
  w[1] = (3 * t3 - 6 * t2 + 4) / 6;
  w[2] = (-3 * t3 + 3 * t2 + 3 * t + 1) / 6;
  w[3] = t3 / 6;
}

// One axis of one level: n fine samples, m coarse samples at k * s (k = 0..m-1, the last at or
// beyond n - 1).
struct AxisPlan {
  int m = 0;
  // Decimation: coarse k = sum of weights[offset[k] + j] * fine[first[k] + j], j < count[k];
  // a tent of half-width s centred on k * s, clamp-to-edge folded into the end samples.
  std::vector<int> first, count, offset;
  std::vector<float> weights;
  // Reconstruction: fine p = sum over q < 4 of spline_w[4p + q] * coarse[spline_i[4p + q]].
  std::vector<int> spline_i;
  std::vector<float> spline_w;

  AxisPlan(int n, double s) {
    m = static_cast<int>(std::ceil((n - 1) / s - 1e-9)) + 1;
    m = std::max(m, 2);
    for (int k = 0; k < m; ++k) {
      const double c = k * s;
      const int lo = static_cast<int>(std::floor(c - s)) + 1;
      const int hi = static_cast<int>(std::ceil(c + s)) - 1;
      const int f = std::clamp(lo, 0, n - 1), l = std::clamp(hi, 0, n - 1);
      first.push_back(f);
      count.push_back(l - f + 1);
      offset.push_back(static_cast<int>(weights.size()));
      weights.resize(weights.size() + (l - f + 1), 0.0f);
      double sum = 0;
      for (int j = lo; j <= hi; ++j) {
        const double w = std::max(0.0, 1.0 - std::abs(j - c) / s);
        weights[offset.back() + (std::clamp(j, 0, n - 1) - f)] += static_cast<float>(w);
        sum += w;
      }
      for (int j = 0; j < count.back(); ++j)
        weights[offset.back() + j] = static_cast<float>(weights[offset.back() + j] / sum);
    }
    spline_i.resize(4 * static_cast<std::size_t>(n));
    spline_w.resize(4 * static_cast<std::size_t>(n));
    for (int p = 0; p < n; ++p) {
      const double u = p / s;
      const int k0 = static_cast<int>(std::floor(u));
      bspline_weights(static_cast<float>(u - k0), &spline_w[4 * static_cast<std::size_t>(p)]);
      for (int q = 0; q < 4; ++q) spline_i[4 * p + q] = std::clamp(k0 - 1 + q, 0, m - 1);
    }
  }
};

// dst[x] += w * src[x] over a row: the vectorised inner loop of both y passes.
void axpy(float* __restrict dst, const float* __restrict src, float w, int n) {
  for (int x = 0; x < n; ++x) dst[x] += w * src[x];
}

}  // namespace

void HeightPyramid::build(const data::HeightField& field, float height_scale,
                          const PyramidParams& params) {
  HorizonParams hp;
  hp.height_scale = height_scale;
  validate_horizon_input(field, hp, TexelRect::all(field));
  if (params.level_step < 1 || params.level_step > kMaxLevelStep)
    throw std::invalid_argument(field.source + ": pyramid level step " +
                                std::to_string(params.level_step) + " must be in [1, " +
                                std::to_string(kMaxLevelStep) + "]");

  width_ = field.width;
  height_ = field.height;
  cell_size_ = field.cell_size;
  level_step_ = params.level_step;
  source_ = field.source;
  // n = ceil(ls * log2(br)) + 1 ([Meier13] eq. 4.4); the epsilon keeps exact powers of two exact.
  const double br = std::max(width_, height_);
  levels_ = static_cast<int>(std::ceil(level_step_ * std::log2(br) - 1e-9)) + 1;

  const std::size_t plane = static_cast<std::size_t>(width_) * height_;
  data_.resize(static_cast<std::size_t>(levels_) * plane);
  float* level0 = data_.data();
  for (std::size_t i = 0; i < plane; ++i) level0[i] = height_scale * field.heights[i];

  const int w = width_, h = height_;
  for (int level = 1; level < levels_; ++level) {
    const double s = std::exp2(static_cast<double>(level) / level_step_);  // sr^i
    const AxisPlan px(w, s), py(h, s);
    const std::size_t rows = static_cast<std::size_t>(py.m) * w;
    scratch_.assign(2 * rows + static_cast<std::size_t>(py.m) * px.m, 0.0f);
    float* dec_y = scratch_.data();  // py.m x w: decimated along y
    float* rec_x = dec_y + rows;     // py.m x w: coarse rows rebuilt along x
    float* coarse = rec_x + rows;    // py.m x px.m: the decimated level
    for (int l = 0; l < py.m; ++l)
      for (int j = 0; j < py.count[l]; ++j)
        axpy(dec_y + static_cast<std::size_t>(l) * w,
             level0 + static_cast<std::size_t>(py.first[l] + j) * w, py.weights[py.offset[l] + j],
             w);
    for (int l = 0; l < py.m; ++l) {
      const float* src = dec_y + static_cast<std::size_t>(l) * w;
      float* c = coarse + static_cast<std::size_t>(l) * px.m;
      for (int k = 0; k < px.m; ++k) {
        float acc = 0;
        for (int j = 0; j < px.count[k]; ++j)
          acc += px.weights[px.offset[k] + j] * src[px.first[k] + j];
        c[k] = acc;
      }
      float* r = rec_x + static_cast<std::size_t>(l) * w;
      for (int x = 0; x < w; ++x) {
        const int* i = &px.spline_i[4 * static_cast<std::size_t>(x)];
        const float* wt = &px.spline_w[4 * static_cast<std::size_t>(x)];
        r[x] = wt[0] * c[i[0]] + wt[1] * c[i[1]] + wt[2] * c[i[2]] + wt[3] * c[i[3]];
      }
    }
    float* dst = data_.data() + static_cast<std::size_t>(level) * plane;
    std::fill(dst, dst + plane, 0.0f);
    for (int y = 0; y < h; ++y)
      for (int q = 0; q < 4; ++q)
        axpy(dst + static_cast<std::size_t>(y) * w,
             rec_x + static_cast<std::size_t>(py.spline_i[4 * y + q]) * w, py.spline_w[4 * y + q],
             w);
  }
}

float HeightPyramid::sample(int level, float x, float y) const {
  assert(level >= 0 && level < levels_);
  x = std::clamp(x, 0.0f, static_cast<float>(width_ - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(height_ - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int dx = x0 + 1 < width_ ? 1 : 0;  // the last column / row: weight 0 on the next
  const std::size_t dy = y0 + 1 < height_ ? static_cast<std::size_t>(width_) : 0;
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const float* row = level_data(level) + static_cast<std::size_t>(y0) * width_ + x0;
  const float top = row[0] + fx * (row[dx] - row[0]);
  const float bottom = row[dy] + fx * (row[dy + dx] - row[dy]);
  return top + fy * (bottom - top);
}

}  // namespace penumbra::terrain_shadow
