#include "penumbra/systems/terrain_shadow/light_horizon_march.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fast_math.h"
#include "march_spline.h"
#include "sweep_geometry.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;
using detail::kPi;

using detail::knot_value;  // [Meier13] eq. 4.8-4.12
using detail::mid_value;

}  // namespace

LightHorizonMarch::LightHorizonMarch(const HeightPyramid& pyramid, const MarchParams& march)
    : pyramid_(&pyramid) {
  const std::string name = pyramid.source().empty() ? "height field" : pyramid.source();
  if (pyramid.levels() == 0)
    throw std::invalid_argument(name + ": light horizon march: the pyramid has not been built");
  if (!(march.level_offset >= 0) || !std::isfinite(march.level_offset))
    throw std::invalid_argument(name + ": light horizon march: level offset " +
                                std::to_string(march.level_offset) + " must be finite and >= 0");
  const int n = pyramid.levels();
  const double sr = std::exp2(1.0 / pyramid.level_step());
  const double shift = pyramid.level_step() * static_cast<double>(march.level_offset);
  double di = 1, spacing = 1;
  for (int i = 0; i < n; ++i) {
    d_.push_back(static_cast<float>(di));
    inv_metres_.push_back(static_cast<float>(1.0 / (di * pyramid.cell_size())));
    // Eq. 4.14 with level 0 the finest (horizon_march.h).
    level_.push_back(
        pyramid.level_data(std::clamp(static_cast<int>(std::ceil(i - shift - 1e-9)), 0, n - 1)));
    di += spacing;
    spacing *= sr;
  }
}

float LightHorizonMarch::horizon(int x, int y, glm::vec2 dir, float limit) const {
  const int n = samples();
  // Eq. 4.24: samples up to the first one beyond the light; reach: the light as a spline
  // parameter (knot i at d_i, linear in between).
  const int beyond = static_cast<int>(std::upper_bound(d_.begin(), d_.end(), limit) - d_.begin());
  if (beyond == 0) return -kHalfPi;
  const int last = std::min(beyond, n - 1);
  const float reach = beyond == n ? static_cast<float>(n - 1)
                                  : static_cast<float>(beyond - 1) +
                                        (limit - d_[beyond - 1]) / (d_[beyond] - d_[beyond - 1]);
  const int w = pyramid_->width(), h = pyramid_->height();
  const float h0 = pyramid_->level_data(0)[static_cast<std::size_t>(y) * w + x];
  constexpr int kStack = 128;
  std::array<float, kStack> stack;
  std::vector<float> heap;
  float* a = stack.data();
  if (last + 1 > kStack) {
    heap.resize(static_cast<std::size_t>(last) + 1);
    a = heap.data();
  }
  int count = 0;
  for (int i = 0; i <= last; ++i) {
    int ox, oy;
    float fx, fy;
    detail::split_offset(d_[i] * dir.x, ox, fx);
    detail::split_offset(d_[i] * dir.y, oy, fy);
    const int sx = fx > 0 ? 1 : 0, sy = fy > 0 ? 1 : 0;
    const int px = x + ox, py = y + oy;
    // Footprints outside the field are dropped; rays are straight, so the rest are too.
    if (px < 0 || py < 0 || px + sx > w - 1 || py + sy > h - 1) break;
    const float* r0 = level_[i] + static_cast<std::size_t>(py) * w + px;
    const float* r1 = r0 + static_cast<std::size_t>(sy) * w;
    const float top = r0[0] + fx * (r0[sx] - r0[0]);
    const float bottom = r1[0] + fx * (r1[sx] - r1[0]);
    a[count++] = (top + fy * (bottom - top) - h0) * inv_metres_[i];  // eq. 4.5-4.6
  }
  if (count == 0) return -kHalfPi;
  detail::fast_atan_array(a, static_cast<std::size_t>(count));
  auto at = [&](int i) { return a[std::clamp(i, 0, count - 1)]; };
  // Eq. 4.13 and 4.25: the spline's maximum over knots and mid-points up to the light.
  float best = -std::numeric_limits<float>::infinity();
  for (int i = 0; i < count; ++i) {
    if (static_cast<float>(i) <= reach)
      best = std::max(best, knot_value(at(i - 1), at(i), at(i + 1)));
    if (i + 1 < count && i + 0.5f <= reach)
      best = std::max(best, mid_value(at(i - 1), at(i), at(i + 1), at(i + 2)));
  }
  if (reach > 0 && reach < static_cast<float>(count - 1)) {  // the spline at the light itself
    const int j = static_cast<int>(reach);
    const float t = reach - static_cast<float>(j), t2 = t * t, t3 = t2 * t;
    const float wt[4] = {(1 - t) * (1 - t) * (1 - t) / 6, (3 * t3 - 6 * t2 + 4) / 6,
                         (-3 * t3 + 3 * t2 + 3 * t + 1) / 6, t3 / 6};  // eq. 4.9-4.12
    float v = 0;
    for (int q = 0; q < 4; ++q) v += wt[q] * at(j - 1 + q);
    best = std::max(best, v);
  }
  return best == -std::numeric_limits<float>::infinity() ? -kHalfPi : best;
}

}  // namespace penumbra::terrain_shadow
