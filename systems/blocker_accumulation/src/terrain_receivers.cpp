#include "penumbra/systems/blocker_accumulation/terrain_receivers.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"

namespace penumbra::blocker_accumulation {

terrain_shadow::TexelRect reached_texels(const TerrainReceivers& t, const WorldSphere& s,
                                         float min_sin) {
  const data::HeightField& f = *t.field;
  const float reach = influence_radius(s.radius, min_sin);
  if (!(s.radius > 0) || !std::isfinite(reach)) return {0, 0, f.width, f.height};
  const float lx = (s.centre.x - reach - t.origin.x) / f.cell_size;
  const float hx = (s.centre.x + reach - t.origin.x) / f.cell_size;
  const float ly = (s.centre.y - reach - t.origin.y) / f.cell_size;
  const float hy = (s.centre.y + reach - t.origin.y) / f.cell_size;
  terrain_shadow::TexelRect r;
  r.x0 = std::clamp(static_cast<int>(std::ceil(lx)), 0, f.width);
  r.x1 = std::clamp(static_cast<int>(std::floor(hx)) + 1, 0, f.width);
  r.y0 = std::clamp(static_cast<int>(std::ceil(ly)), 0, f.height);
  r.y1 = std::clamp(static_cast<int>(std::floor(hy)) + 1, 0, f.height);
  return r;
}

template <int N>
TerrainShadeStats update_terrain_ratios(const TerrainReceivers& t,
                                        const BlockerAccumulation<N>& blockers,
                                        const terrain_shadow::LogWedge<N>& wedges,
                                        const sh::CoeffsRgb<N>& radiance,
                                        std::vector<glm::vec3>& ratio, int phase, int period,
                                        int stride) {
  const data::HeightField& f = *t.field;
  const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
  if (t.normals->size() != n || t.horizons->width != f.width || t.horizons->height != f.height ||
      t.horizons->azimuths != wedges.azimuths())
    throw std::invalid_argument("terrain receivers: " + f.source +
                                ": normals or horizons do not match the field");
  if (period < 1) period = 1;
  if (stride < 1) stride = 1;
  if (ratio.size() != n) ratio.assign(n, glm::vec3(1.0f));
  // The lattice of texels shaded: every stride-th one along x and y, and the last ones.
  const auto on_lattice = [stride](int v, int size) { return v % stride == 0 || v == size - 1; };
  // Which texels some blocker reaches: a mask over the union of their rectangles.
  std::vector<unsigned char> mask(n, 0);
  const float min_sin = blockers.settings().blocker.min_sin;
  for (const WorldSphere& s : blockers.blockers()) {
    const terrain_shadow::TexelRect r = reached_texels(t, s, min_sin);
    for (int y = r.y0; y < r.y1; ++y)
      std::fill_n(mask.begin() + static_cast<std::ptrdiff_t>(y) * f.width + r.x0, r.width(), 1);
  }
  const sh::Zonal<N> cosine = sh::zh_clamped_cosine<N>();
  constexpr float kY00 = 0.28209479f;
  constexpr float kNegligibleLog = 0.01f;  // about 1% of the visibility, averaged
  std::atomic<std::size_t> reached{0}, changed{0};
  const auto recomputed = [&](int y) {  // a lattice row of this call's phase
    return on_lattice(y, f.height) && (y / stride) % period == phase % period;
  };
  tbb::parallel_for(0, f.height, [&](int y) {
    if (!recomputed(y)) return;
    std::size_t row_reached = 0, row_changed = 0;
    for (int x = 0; x < f.width; ++x) {
      if (!on_lattice(x, f.width)) continue;
      const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
      ratio[i] = glm::vec3(1.0f);
      if (!mask[i]) continue;
      ++row_reached;
      const glm::vec3 p =
          t.origin + glm::vec3(x * f.cell_size, y * f.cell_size, t.height_scale * f.at(x, y));
      const glm::vec3& nn = (*t.normals)[i];
      const sh::Coeffs<N> blocked = blockers.log_visibility(p, nn);
      // Mean log-visibility under half the threshold: no visible change, skipped; up to the
      // threshold the ratio fades in, so the skipped region meets the shaded one without a step.
      const float depth = -blocked[0] * kY00;
      if (depth < 0.5f * kNegligibleLog) continue;
      const float u = std::min(1.0f, (depth - 0.5f * kNegligibleLog) / (0.5f * kNegligibleLog));
      const float fade = u * u * (3 - 2 * u);
      const sh::Coeffs<N> terrain = wedges.log_visibility(t.horizons->texel(x, y));
      sh::Coeffs<N> both = terrain;
      for (int k = 0; k < N * N; ++k) both[k] += blocked[k];  // one sum, one exponential
      const sh::Coeffs<N> lobe = sh::rotate_zh<N>(cosine, nn);
      const sh::Coeffs<N> t_alone = sh::product<N>(sh::exp_visibility<N>(terrain), lobe);
      const sh::Coeffs<N> t_both = sh::product<N>(sh::exp_visibility<N>(both), lobe);
      for (int c = 0; c < 3; ++c) {
        const float alone = sh::dot<N>(radiance[c], t_alone);
        const float open = radiance[c][0] * 0.8862269f;  // sqrt(pi) / 2 L_00: open-sky irradiance
        if (alone > 1e-6f * std::abs(open))
          ratio[i][c] =
              1 + fade * (std::clamp(sh::dot<N>(radiance[c], t_both) / alone, 0.0f, 1.0f) - 1);
      }
      ++row_changed;
    }
    reached += row_reached;
    changed += row_changed;
  });
  if (stride > 1) {  // the texels between lattice points: bilinear in the lattice's ratios
    const auto bracket = [stride](int v, int size, int& v0, int& v1, float& a) {
      v0 = std::min(v / stride * stride, size - 1);
      v1 = std::min(v0 + stride, size - 1);
      a = v1 > v0 ? static_cast<float>(v - v0) / static_cast<float>(v1 - v0) : 0.0f;
    };
    tbb::parallel_for(0, f.height, [&](int y) {
      int y0, y1;
      float ay;
      bracket(y, f.height, y0, y1, ay);
      if (!recomputed(y0) && !recomputed(y1)) return;  // its lattice rows kept their values
      const glm::vec3* r0 = &ratio[static_cast<std::size_t>(y0) * f.width];
      const glm::vec3* r1 = &ratio[static_cast<std::size_t>(y1) * f.width];
      glm::vec3* out = &ratio[static_cast<std::size_t>(y) * f.width];
      const bool lattice_row = on_lattice(y, f.height);
      for (int x = 0; x < f.width; ++x) {
        if (lattice_row && on_lattice(x, f.width)) continue;
        int x0, x1;
        float ax;
        bracket(x, f.width, x0, x1, ax);
        out[x] =
            (1 - ay) * ((1 - ax) * r0[x0] + ax * r0[x1]) + ay * ((1 - ax) * r1[x0] + ax * r1[x1]);
      }
    });
  }
  return {reached.load(), changed.load()};
}

template <int N>
std::vector<glm::vec3> shade_terrain_receivers(const TerrainReceivers& t,
                                               const BlockerAccumulation<N>& blockers,
                                               const terrain_shadow::LogWedge<N>& wedges,
                                               const sh::CoeffsRgb<N>& radiance,
                                               const std::vector<glm::vec3>& base,
                                               TerrainShadeStats* stats) {
  if (base.size() != static_cast<std::size_t>(t.field->width) * t.field->height)
    throw std::invalid_argument("terrain receivers: " + t.field->source +
                                ": lighting does not match the field");
  std::vector<glm::vec3> ratio;
  const TerrainShadeStats s = update_terrain_ratios<N>(t, blockers, wedges, radiance, ratio);
  if (stats) *stats = s;
  std::vector<glm::vec3> out = base;
  for (std::size_t i = 0; i < out.size(); ++i) out[i] *= ratio[i];
  return out;
}

template TerrainShadeStats update_terrain_ratios<4>(const TerrainReceivers&,
                                                    const BlockerAccumulation<4>&,
                                                    const terrain_shadow::LogWedge<4>&,
                                                    const sh::CoeffsRgb<4>&,
                                                    std::vector<glm::vec3>&, int, int, int);
template std::vector<glm::vec3> shade_terrain_receivers<4>(
    const TerrainReceivers&, const BlockerAccumulation<4>&, const terrain_shadow::LogWedge<4>&,
    const sh::CoeffsRgb<4>&, const std::vector<glm::vec3>&, TerrainShadeStats*);

}  // namespace penumbra::blocker_accumulation
