#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"

#include <algorithm>
#include <numbers>

#include <glm/geometric.hpp>

namespace penumbra::blocker_accumulation {
namespace {
float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}
}  // namespace

BlockerView view_blocker(const glm::vec3& p, const glm::vec3& n, const glm::vec3& centre,
                         float radius, const SphereBlockerSettings& s) {
  BlockerView v;
  if (!(radius > 0)) return v;
  const float t = glm::dot(n, centre - p) + radius;  // reach above the tangent plane
  if (!(t > 0)) return v;
  const float r1 = std::min(radius, 0.5f * t);  // [Guerrero08] sec. 6.2: the part above the plane
  const glm::vec3 c1 = centre + (radius - r1) * n;
  const glm::vec3 to = c1 - p;
  const float d = glm::length(to);
  if (!(d > 0)) return v;
  v.axis = to / d;
  v.sin_angle = std::min(r1 / d, 1.0f);  // [Giraud] eq. 24, arcsine guarded
  v.weight = smoothstep01(t / (2 * radius));
  if (s.min_sin > 0) v.weight *= smoothstep01((v.sin_angle - s.min_sin) / s.min_sin);
  if (s.ratio == RatioAttenuation::kOn) v.weight *= v.sin_angle;  // [Giraud] sec. 4.2, r / |c - p|
  return v;
}

template <int N>
void add_log_visibility(const BlockerView& v, float log_eps, sh::Coeffs<N>& log_visibility) {
  if (!(v.weight > 0)) return;
  const float x = std::sqrt(std::max(0.0f, 1 - v.sin_angle * v.sin_angle));  // cos(half-angle)
  // Legendre P_0..P_N at x (P_N is needed for the band N-1 difference).
  float p[N + 1];
  p[0] = 1;
  p[1] = x;
  for (int l = 1; l < N; ++l) p[l + 1] = ((2 * l + 1) * x * p[l] - l * p[l - 1]) / (l + 1);
  float y[N * N];
  sh::eval_basis<N>(v.axis, y);
  const float scale = log_eps * v.weight * 2 * std::numbers::pi_v<float>;
  for (int l = 0; l < N; ++l) {
    const float below = l == 0 ? 1.0f : p[l - 1];
    const float k = scale * (below - p[l + 1]) / static_cast<float>(2 * l + 1);  // [Giraud] eq. 26
    for (int m = -l; m <= l; ++m) log_visibility[sh::index(l, m)] += k * y[sh::index(l, m)];
  }
}

#define PENUMBRA_BLOCKER_INSTANTIATE(N) \
  template void add_log_visibility<N>(const BlockerView&, float, sh::Coeffs<N>&);
PENUMBRA_BLOCKER_INSTANTIATE(3)
PENUMBRA_BLOCKER_INSTANTIATE(4)
PENUMBRA_BLOCKER_INSTANTIATE(5)
PENUMBRA_BLOCKER_INSTANTIATE(6)
#undef PENUMBRA_BLOCKER_INSTANTIATE

}  // namespace penumbra::blocker_accumulation
