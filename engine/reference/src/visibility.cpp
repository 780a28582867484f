// SH projection of binary visibility, V_i = int V(p, w) y_i(w) W(w) dw, by stratified
// equal-area sampling of the sphere, the hemisphere, or cosine-weighted hemisphere directions.
#include <array>
#include <limits>
#include <numbers>

#include "common.h"
#include "penumbra/reference/sampling.h"

namespace penumbra::reference {
namespace {

template <int N>
ShEstimate<N> visibility_estimate(const Scene& scene, const Receiver& r, std::size_t index,
                                  const VisibilityOptions& o) {
  constexpr int kCount = N * N;
  const detail::Shading s = detail::shading(scene, r, o.ray_offset);
  // Direction warp and the constant W(w) / pdf(w) of each domain.
  const bool sphere = o.domain == VisibilityDomain::kSphere;
  const double weight = sphere                                      ? 4 * std::numbers::pi
                        : o.domain == VisibilityDomain::kHemisphere ? 2 * std::numbers::pi
                                                                    : std::numbers::pi;
  const Frame frame(sphere ? glm::vec3(0, 0, 1) : s.n);
  const StrataGrid grid = StrataGrid::for_count(o.samples / 2, o.stratified);
  Pcg32 rng(o.seed, index, detail::kVisibilitySalt);
  PairedMean<kCount> acc;
  float y[kCount];
  for (int h = 0; h < grid.count(); ++h) {
    std::array<double, kCount> g[2] = {};
    for (auto& gk : g) {
      const glm::vec2 u = to_float(grid.point(h, rng));
      const glm::vec3 local = o.domain == VisibilityDomain::kSphere       ? uniform_sphere(u)
                              : o.domain == VisibilityDomain::kHemisphere ? uniform_hemisphere(u)
                                                                          : cosine_hemisphere(u);
      const glm::vec3 dir = sphere ? local : frame.to_world(local);
      if (!sphere && !(local.z > 0)) continue;  // measure zero; keeps W / pdf exact
      if (scene.occluded(s.origin, dir, std::numeric_limits<float>::infinity())) continue;
      sh::eval_basis<N>(dir, y);
      for (int i = 0; i < kCount; ++i) gk[i] = weight * y[i];
    }
    acc.add_pair(g[0], g[1]);
  }
  ShEstimate<N> out;
  for (int i = 0; i < kCount; ++i) {
    out.mean[i] = static_cast<float>(acc.mean(i));
    out.std_error[i] = static_cast<float>(acc.std_error(i));
  }
  out.samples = out.rays = static_cast<std::uint32_t>(2 * grid.count());
  out.dof = static_cast<std::uint32_t>(acc.dof());
  return out;
}

}  // namespace

template <int N>
std::vector<ShEstimate<N>> visibility_sh(const Scene& scene, std::span<const Receiver> receivers,
                                         const VisibilityOptions& options) {
  constexpr const char* kFn = "reference::visibility_sh";
  static_assert(N >= 2 && N <= sh::kMaxBands);
  detail::check_options(options, kFn);
  detail::check_receivers(receivers, options.domain == VisibilityDomain::kSphere, kFn);
  std::vector<ShEstimate<N>> out(receivers.size());
  detail::for_each_receiver(receivers.size(), [&](std::size_t i) {
    out[i] = visibility_estimate<N>(scene, receivers[i], i, options);
  });
  return out;
}

template std::vector<ShEstimate<2>> visibility_sh<2>(const Scene&, std::span<const Receiver>,
                                                     const VisibilityOptions&);
template std::vector<ShEstimate<3>> visibility_sh<3>(const Scene&, std::span<const Receiver>,
                                                     const VisibilityOptions&);
template std::vector<ShEstimate<4>> visibility_sh<4>(const Scene&, std::span<const Receiver>,
                                                     const VisibilityOptions&);
template std::vector<ShEstimate<5>> visibility_sh<5>(const Scene&, std::span<const Receiver>,
                                                     const VisibilityOptions&);
template std::vector<ShEstimate<6>> visibility_sh<6>(const Scene&, std::span<const Receiver>,
                                                     const VisibilityOptions&);

}  // namespace penumbra::reference
