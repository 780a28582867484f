#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "fast_math.h"
#include "penumbra/systems/terrain_shadow/cap_transfer.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/light_horizon_march.h"
#include "penumbra/systems/terrain_shadow/radial_horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/transfer.h"

namespace penumbra::terrain_shadow {

const char* to_string(HorizonMethod m) {
  switch (m) {
    case HorizonMethod::kSweep:
      return "sweep";
    case HorizonMethod::kMarch:
      return "march";
    case HorizonMethod::kBruteForce:
      return "brute_force";
  }
  return "?";
}

const char* to_string(LightWedgeHorizons h) {
  switch (h) {
    case LightWedgeHorizons::kMarch:
      return "march";
    case LightWedgeHorizons::kBruteForce:
      return "brute_force";
  }
  return "?";
}

const char* to_string(CapHorizons h) {  // the names the benchmark records use
  switch (h) {
    case CapHorizons::kRadialSweep:
      return "sweep";
    case CapHorizons::kMarch:
      return "march";
    case CapHorizons::kRays:
      return "brute_force";
  }
  return "?";
}

const char* to_string(TransferMethod t) {
  switch (t) {
    case TransferMethod::kExact:
      return "exact";
    case TransferMethod::kTruncatedProduct:
      return "truncated";
  }
  return "?";
}

const char* to_string(LightShading s) {
  switch (s) {
    case LightShading::kShWedges:
      return "sh_wedges";
    case LightShading::kCapHorizon:
      return "cap_horizon";
  }
  return "?";
}

namespace {

// out += radiance e, by multiply-adds (add_lit8's floats).
void add_lit(const glm::vec3& radiance, float e, glm::vec3& out) {
  out = {std::fma(radiance.x, e, out.x), std::fma(radiance.y, e, out.y),
         std::fma(radiance.z, e, out.z)};
}

// add_lit on eight consecutive texels (24 packed floats) with three vector multiply-adds; a
// lane with e = 0 adds nothing, as add_lit's caller skips it.
void add_lit8(const glm::vec3& radiance, const float* e, glm::vec3* out) {
#ifdef __AVX2__
  float* o = &out[0].x;
  const __m256 ev = _mm256_loadu_ps(e);
  const __m256 r0 = _mm256_setr_ps(radiance.x, radiance.y, radiance.z, radiance.x, radiance.y,
                                   radiance.z, radiance.x, radiance.y);
  const __m256 r1 = _mm256_setr_ps(radiance.z, radiance.x, radiance.y, radiance.z, radiance.x,
                                   radiance.y, radiance.z, radiance.x);
  const __m256 r2 = _mm256_setr_ps(radiance.y, radiance.z, radiance.x, radiance.y, radiance.z,
                                   radiance.x, radiance.y, radiance.z);
  const __m256 e0 = _mm256_permutevar8x32_ps(ev, _mm256_setr_epi32(0, 0, 0, 1, 1, 1, 2, 2));
  const __m256 e1 = _mm256_permutevar8x32_ps(ev, _mm256_setr_epi32(2, 3, 3, 3, 4, 4, 4, 5));
  const __m256 e2 = _mm256_permutevar8x32_ps(ev, _mm256_setr_epi32(5, 5, 6, 6, 6, 7, 7, 7));
  _mm256_storeu_ps(o, _mm256_fmadd_ps(r0, e0, _mm256_loadu_ps(o)));
  _mm256_storeu_ps(o + 8, _mm256_fmadd_ps(r1, e1, _mm256_loadu_ps(o + 8)));
  _mm256_storeu_ps(o + 16, _mm256_fmadd_ps(r2, e2, _mm256_loadu_ps(o + 16)));
#else
  for (int l = 0; l < 8; ++l)
    if (e[l] > 0) add_lit(radiance, e[l], out[l]);
#endif
}

TerrainShadowConfig checked(const TerrainShadowConfig& c) {
  if (c.azimuths < 3 || c.light_azimuths < 3)
    throw std::invalid_argument("terrain shadow config: at least 3 azimuths needed");
  if (c.cap_horizons < 1 || c.cap_horizons > kMaxCapHorizons)
    throw std::invalid_argument("terrain shadow config: cap_horizons must be in [1, " +
                                std::to_string(kMaxCapHorizons) + "], got " +
                                std::to_string(c.cap_horizons));
  if (!(c.cap_wide >= 0))
    throw std::invalid_argument("terrain shadow config: cap_wide must be >= 0");
  if (c.cap_strips < 1 || c.cap_strips > kMaxCapStrips)
    throw std::invalid_argument("terrain shadow config: cap_strips must be in [1, " +
                                std::to_string(kMaxCapStrips) + "], got " +
                                std::to_string(c.cap_strips));
  return c;
}

HorizonParams env_params(const TerrainShadowConfig& c, float scale) {
  HorizonParams p;
  p.azimuths = c.azimuths;
  p.height_scale = scale;
  p.clamp_at_zero = true;
  return p;
}

// Horizons of `region` by `method` (the pyramid must be built for kMarch).
void compute_horizons(HorizonMethod method, const data::HeightField& f,
                      const HeightPyramid& pyramid, const HorizonParams& p,
                      const MarchParams& march, const TexelRect& region, HorizonGrid& out,
                      SweepWorkspace& sweep) {
  switch (method) {
    case HorizonMethod::kSweep:
      sweep_horizons(f, p, region, out, sweep);
      break;
    case HorizonMethod::kMarch:
      // The march is single-threaded per call: bands of 8 rows in parallel (disjoint writes
      // once `out` has the field's size).
      if (out.width != f.width || out.height != f.height || out.azimuths != p.azimuths)
        out.resize(f.width, f.height, p.azimuths);
      tbb::parallel_for(tbb::blocked_range<int>(region.y0, region.y1, 8), [&](const tbb::
                                                                                  blocked_range<
                                                                                      int>& rows) {
        march_horizons(pyramid, p, march, {region.x0, rows.begin(), region.x1, rows.end()}, out);
      });
      break;
    case HorizonMethod::kBruteForce:
      brute_force_horizons(f, p, region, out);
      break;
  }
}

// A light's receivers waiting for their chords (add_cap_light): W lanes of `Lanes`.
template <class Lanes, int W>
struct ChordQueue {
  static constexpr int kWidth = W;
  Lanes batch;
  std::size_t at[W];  // the receivers' texels
  int queued = 0;
  bool varied = false;  // some lane has samples of its own (else one sample is the same)
};

}  // namespace

template <int N>
TerrainShadowing<N>::TerrainShadowing(const TerrainShadowConfig& config)
    : config_(checked(config)),
      frame_(config.azimuths),
      sphere_(config.light_azimuths, WedgeDomain::kSphere, config.table_resolution) {
  if (config_.transfer == TransferMethod::kExact)
    hemisphere_exact_.emplace(config_.azimuths, WedgeDomain::kHemisphere, config_.table_resolution);
  else
    hemisphere_.emplace(config_.azimuths, WedgeDomain::kHemisphere, config_.table_resolution);
  sweep_.set_sole_writer(true);  // horizons_ is written through sweep_ only (update, update_edit)
}

template <int N>
glm::vec3 TerrainShadowing<N>::position(int x, int y) const {
  return {x * field_->cell_size, y * field_->cell_size, height_scale_ * field_->at(x, y)};
}

template <int N>
void TerrainShadowing<N>::compute_normals(const TexelRect& r) {
  const data::HeightField& f = *field_;
  // Central differences, one-sided at the border (as reference::height_field_receivers).
  auto row = [&](int y) {
    for (int x = r.x0; x < r.x1; ++x) {
      const int xa = std::max(x - 1, 0), xb = std::min(x + 1, f.width - 1);
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, f.height - 1);
      const float dx = height_scale_ * (f.at(xb, y) - f.at(xa, y)) / ((xb - xa) * f.cell_size);
      const float dy = height_scale_ * (f.at(x, yb) - f.at(x, ya)) / ((yb - ya) * f.cell_size);
      const glm::vec3 n(-dx, -dy, 1.0f);
      normals_[static_cast<std::size_t>(y) * f.width + x] = n / std::sqrt(glm::dot(n, n));
    }
  };
  // An edit's few rows on this thread (a parallel loop would cost more than its work: waking a
  // worker for a few microseconds' of rows); the field's rows in parallel.
  if (r.count() <= 64 * 64) {
    for (int y = r.y0; y < r.y1; ++y) row(y);
    return;
  }
  tbb::parallel_for(r.y0, r.y1, row);
}

template <int N>
void TerrainShadowing<N>::compute_transfer(const std::vector<std::size_t>* texels) {
  const int w = field_->width;
  const bool exact = config_.transfer == TransferMethod::kExact;
  // The texels (x, y) = texel(0), ..., texel(count - 1): the exact transfer's couplings eight at a
  // time (exact_diffuse_transfer_8, the same bits as one at a time).
  auto run = [&](std::size_t count, auto texel) {
    std::vector<float> raised(exact ? static_cast<std::size_t>(config_.azimuths) : 0);
    std::array<sh::Coeffs<N + 1>, 8> vis;
    std::array<glm::vec3, 8> nrm;
    std::array<sh::Coeffs<N>, 8> res;
    std::array<std::size_t, 8> at;
    int batch = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const auto [x, y] = texel(k);
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (exact) {  // ours (transfer.h): V above the horizon and the tangent plane, N + 1 bands
        frame_.raise_to_tangent_plane(horizons_.texel(x, y), normals_[i], raised.data());
        vis[batch] = hemisphere_exact_->visibility(raised.data());
        nrm[batch] = normals_[i];
        at[batch++] = i;
        if (batch == 8) {
          exact_diffuse_transfer_8<N>(vis.data(), nrm.data(), res.data());
          for (int b = 0; b < 8; ++b) transfer_[at[b]] = res[b];
          batch = 0;
        }
      } else {  // [Meier13] eq. 4.19 then 4.21.
        transfer_[i] =
            diffuse_transfer<N>(hemisphere_->visibility(horizons_.texel(x, y)), normals_[i]);
      }
    }
    for (int b = 0; b < batch; ++b) transfer_[at[b]] = exact_diffuse_transfer<N>(vis[b], nrm[b]);
  };
  if (!texels) {  // every texel, a row per task
    tbb::parallel_for(0, field_->height, [&](int y) {
      run(static_cast<std::size_t>(w),
          [&](std::size_t k) { return std::pair(static_cast<int>(k), y); });
    });
    return;
  }
  // A list (an edit's): blocks of 64, so that batches are whole wherever the texels lie.
  constexpr std::size_t kBlock = 64;
  tbb::parallel_for(std::size_t{0}, (texels->size() + kBlock - 1) / kBlock, [&](std::size_t b) {
    const std::size_t k0 = b * kBlock;
    run(std::min(kBlock, texels->size() - k0), [&](std::size_t k) {
      const std::size_t i = (*texels)[k0 + k];
      return std::pair(static_cast<int>(i % w), static_cast<int>(i / w));
    });
  });
}

template <int N>
UpdateStats TerrainShadowing<N>::update(std::shared_ptr<const data::HeightField> field,
                                        float height_scale) {
  if (!field) throw std::invalid_argument("terrain shadowing: no height field");
  const HorizonParams p = env_params(config_, height_scale);
  validate_horizon_input(*field, p, TexelRect::all(*field));
  field_ = std::move(field);
  height_scale_ = height_scale;
  const data::HeightField& f = *field_;
  const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
  normals_.resize(n);
  transfer_.resize(n);
  compute_normals(TexelRect::all(f));
  pyramid_valid_ = false;
  if (config_.method == HorizonMethod::kMarch ||
      (config_.light_shading == LightShading::kShWedges &&
       config_.light_method == LightWedgeHorizons::kMarch) ||
      (config_.light_shading == LightShading::kCapHorizon &&
       config_.cap_method == CapHorizons::kMarch)) {
    pyramid_.build(f, height_scale, config_.pyramid);
    pyramid_valid_ = true;
  }
  compute_horizons(config_.method, f, pyramid_, p, config_.march, TexelRect::all(f), horizons_,
                   sweep_);
  compute_transfer(nullptr);
  return {true, n * config_.azimuths, n};
}

template <int N>
UpdateStats TerrainShadowing<N>::update_edit(std::shared_ptr<const data::HeightField> field,
                                             float height_scale, TexelRect edited) {
  if (!field_ || !field || field->width != field_->width || field->height != field_->height ||
      height_scale != height_scale_ || config_.method != HorizonMethod::kSweep)
    return update(std::move(field), height_scale);
  const HorizonParams p = env_params(config_, height_scale);
  edited.x0 = std::max(edited.x0, 0);
  edited.y0 = std::max(edited.y0, 0);
  edited.x1 = std::min(edited.x1, field->width);
  edited.y1 = std::min(edited.y1, field->height);
  // Every horizon the edit can change lies on a sweep line passing within a sample of it:
  // recompute those lines exactly as a full sweep would (sweep_horizons_through), then the
  // transfer of texels whose horizons or normal changed. sweep_horizons_through validates the
  // field before it writes anything, so a bad one throws here with this object unchanged.
  // The flags are all zero between edits (cleared below from the list), so an edit does not
  // clear the whole field's.
  std::vector<unsigned char>& changed = edit_flags_;
  UpdateStats stats;
  stats.horizon_pairs = sweep_horizons_through(*field, p, edited, horizons_, changed, sweep_);
  field_ = std::move(field);
  if (edited.empty()) return {};
  const data::HeightField& f = *field_;
  const int w = f.width, h = f.height;

  // Line samples interpolate between neighbouring rows, so the edit reaches one texel further;
  // normals use central differences: also one further.
  const TexelRect e{std::max(edited.x0 - 1, 0), std::max(edited.y0 - 1, 0),
                    std::min(edited.x1 + 1, w), std::min(edited.y1 + 1, h)};
  compute_normals(e);
  if (pyramid_valid_) pyramid_.build(f, height_scale, config_.pyramid);
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) changed[static_cast<std::size_t>(y) * w + x] = 1;
  std::vector<std::size_t> texels;
  std::size_t i = 0;
  for (; i + 32 <= changed.size(); i += 32) {  // 32 flags at a time: most are zero
    std::uint64_t q[4];
    std::memcpy(q, changed.data() + i, 32);
    if ((q[0] | q[1] | q[2] | q[3]) != 0)
      for (std::size_t k = i; k < i + 32; ++k)
        if (changed[k]) texels.push_back(k);
  }
  for (; i < changed.size(); ++i)
    if (changed[i]) texels.push_back(i);
  for (std::size_t t : texels) changed[t] = 0;
  stats.transfer_texels = texels.size();
  compute_transfer(&texels);
  return stats;
}

template <int N>
void TerrainShadowing<N>::shade_environment(const sh::CoeffsRgb<N>& radiance,
                                            std::vector<glm::vec3>& irradiance) const {
  irradiance.resize(transfer_.size());
  tbb::parallel_for(std::size_t{0}, transfer_.size(), std::size_t{1024}, [&](std::size_t i0) {
    const std::size_t i1 = std::min(i0 + 1024, transfer_.size());
    for (std::size_t i = i0; i < i1; ++i)  // [Meier13] eq. 4.21
      irradiance[i] = {sh::dot<N>(radiance[0], transfer_[i]), sh::dot<N>(radiance[1], transfer_[i]),
                       sh::dot<N>(radiance[2], transfer_[i])};
  });
}

template <int N>
void TerrainShadowing<N>::shade_environment(const sh::CoeffsRgb<N>& radiance,
                                            std::vector<glm::vec3>& irradiance,
                                            std::span<const TexelRect> regions) const {
  if (!field_) throw std::invalid_argument("terrain shadowing: shade_environment before update");
  if (irradiance.size() != transfer_.size())
    throw std::invalid_argument("shade_environment: irradiance is not one per texel");
  const int w = field_->width;
  tbb::parallel_for(std::size_t{0}, regions.size(), [&](std::size_t k) {
    const TexelRect& r = regions[k];
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {  // [Meier13] eq. 4.21, as above
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        irradiance[i] = {sh::dot<N>(radiance[0], transfer_[i]),
                         sh::dot<N>(radiance[1], transfer_[i]),
                         sh::dot<N>(radiance[2], transfer_[i])};
      }
  });
}

template <int N>
void TerrainShadowing<N>::validate_light(const glm::vec3& centre, float radius,
                                         const glm::vec3& radiance) const {
  if (!field_) throw std::invalid_argument("terrain shadowing: add_spherical_light before update");
  if (!(std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z)) ||
      !std::isfinite(radius) || radius < 0 || !std::isfinite(radiance.x) ||
      !std::isfinite(radiance.y) || !std::isfinite(radiance.z) || radiance.x < 0 ||
      radiance.y < 0 || radiance.z < 0)
    throw std::invalid_argument(
        "spherical light: centre, radius and radiance must be finite, radius and radiance >= 0");
}

template <int N>
void TerrainShadowing<N>::add_spherical_light(const glm::vec3& centre, float radius,
                                              const glm::vec3& radiance,
                                              std::vector<glm::vec3>& irradiance) {
  validate_light(centre, radius, radiance);
  const data::HeightField& f = *field_;
  irradiance.resize(static_cast<std::size_t>(f.width) * f.height, glm::vec3(0.0f));
  if (radius == 0) return;
  std::vector<Span> rows(static_cast<std::size_t>(f.height));
  for (int y = 0; y < f.height; ++y) rows[static_cast<std::size_t>(y)] = {y, 0, f.width};
  if (config_.light_shading == LightShading::kCapHorizon)
    add_cap_light(centre, radius, radiance, irradiance, rows,
                  std::numeric_limits<float>::infinity(), {});
  else
    add_sh_light(centre, radius, radiance, irradiance, rows);
}

template <int N>
void TerrainShadowing<N>::add_spherical_light(const glm::vec3& centre, float radius,
                                              const glm::vec3& radiance,
                                              std::vector<glm::vec3>& irradiance,
                                              std::span<const TexelRect> regions) {
  validate_light(centre, radius, radiance);
  const data::HeightField& f = *field_;
  if (irradiance.size() != static_cast<std::size_t>(f.width) * f.height)
    throw std::invalid_argument("add_spherical_light: irradiance needs one value per texel");
  if (radius == 0) return;
  std::vector<Span> spans;
  float reach = 0;
  for (const TexelRect& r : regions) {
    const TexelRect c{std::max(r.x0, 0), std::max(r.y0, 0), std::min(r.x1, f.width),
                      std::min(r.y1, f.height)};
    if (c.empty()) continue;
    for (int y = c.y0; y < c.y1; ++y) spans.push_back({y, c.x0, c.x1});
    for (int k = 0; k < 4; ++k) {  // the farthest corner from the light's foot
      const glm::vec2 corner(static_cast<float>(k & 1 ? c.x1 - 1 : c.x0),
                             static_cast<float>(k & 2 ? c.y1 - 1 : c.y0));
      reach = std::max(reach, glm::length(corner * f.cell_size - glm::vec2(centre)));
    }
  }
  if (spans.empty()) return;
  if (config_.light_shading == LightShading::kCapHorizon)
    add_cap_light(centre, radius, radiance, irradiance, spans, reach + f.cell_size, regions);
  else
    add_sh_light(centre, radius, radiance, irradiance, spans);
}

// Spans with a texel outside the light and not wholly behind its tangent plane.
template <int N>
bool TerrainShadowing<N>::span_lit(const Span& s, const glm::vec3& centre, float radius) const {
  for (int x = s.x0; x < s.x1; ++x) {
    const glm::vec3 d = centre - position(x, s.y);
    if (glm::dot(d, d) > radius * radius &&
        glm::dot(d, normals_[static_cast<std::size_t>(s.y) * field_->width + x]) > -radius)
      return true;
  }
  return false;
}

template <int N>
void TerrainShadowing<N>::add_sh_light(const glm::vec3& centre, float radius,
                                       const glm::vec3& radiance,
                                       std::vector<glm::vec3>& irradiance,
                                       const std::vector<Span>& spans) {
  const data::HeightField& f = *field_;
  HorizonParams p;
  p.azimuths = config_.light_azimuths;
  p.height_scale = height_scale_;
  p.clamp_at_zero = false;
  p.limit_to_point = glm::vec2(centre.x, centre.y);
  if (light_horizons_.width != f.width || light_horizons_.height != f.height ||
      light_horizons_.azimuths != p.azimuths)
    light_horizons_.resize(f.width, f.height, p.azimuths);
  tbb::parallel_for(std::size_t{0}, spans.size(), [&](std::size_t si) {
    const Span& span = spans[si];
    const int y = span.y;
    if (!span_lit(span, centre, radius)) return;
    const TexelRect row{span.x0, y, span.x1, y + 1};
    // [Meier13] eq. 4.22-4.25 (row by row: rows are the parallel tiles).
    if (config_.light_method == LightWedgeHorizons::kMarch)
      march_horizons(pyramid_, p, config_.march, row, light_horizons_);
    else
      for (int x = span.x0; x < span.x1; ++x)
        for (int k = 0; k < p.azimuths; ++k)
          light_horizons_.texel(x, y)[k] = ray_horizon(
              f, height_scale_, glm::vec2(x, y), height_scale_ * f.at(x, y),
              static_cast<float>(2.0 * std::numbers::pi * k / p.azimuths),
              glm::length(glm::vec2(centre.x, centre.y) - glm::vec2(x, y) * f.cell_size), false);
    for (int x = span.x0; x < span.x1; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
      const glm::vec3 d = centre - position(x, y);
      if (glm::dot(d, d) <= radius * radius || glm::dot(d, normals_[i]) <= -radius) continue;
      // [Meier13] eq. 4.26-4.29.
      const sh::Coeffs<N> t =
          diffuse_transfer<N>(sphere_.visibility(light_horizons_.texel(x, y)), normals_[i]);
      const float e = sh::dot<N>(spherical_light_radiance<N>(d, radius), t);
      irradiance[i] += radiance * std::max(e, 0.0f);
    }
  });
}

template <int N>
void TerrainShadowing<N>::add_cap_light(const glm::vec3& centre, float radius,
                                        const glm::vec3& radiance,
                                        std::vector<glm::vec3>& irradiance,
                                        const std::vector<Span>& spans, float reach,
                                        std::span<const TexelRect> regions) {
  const data::HeightField& f = *field_;
  const CapHorizons method = config_.cap_method;
  std::optional<LightHorizonMarch> marcher;
  if (method == CapHorizons::kMarch) marcher.emplace(pyramid_, config_.march);
  if (method == CapHorizons::kRadialSweep)
    radial_.run(f, height_scale_, glm::vec2(centre.x, centre.y), reach, regions);
  const bool sweep = method == CapHorizons::kRadialSweep;
  // One receiver (kMarch, kRays): the cap, its cap_horizons horizons and cap_transfer.
  auto shade = [&](int x, int y) {
    const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
    const glm::vec3 d = centre - position(x, y);
    LightCap cap;
    if (glm::dot(d, normals_[i]) <= -radius || !make_light_cap(d, radius, cap)) return;
    // Horizons towards the cap only, limited to the light's plane distance ([Meier13] eq. 4.22).
    std::array<float, kMaxCapHorizons> horizon;
    const int count = config_.cap_horizons;
    for (int j = 0; j < count; ++j) {
      const glm::vec2 dir = cap_horizon_direction(cap, j, count);
      horizon[j] = method == CapHorizons::kMarch
                       ? marcher->horizon(x, y, dir, cap.plane_distance / f.cell_size)
                       : ray_horizon(f, height_scale_, glm::vec2(x, y), height_scale_ * f.at(x, y),
                                     dir, cap.plane_distance, false);
    }
    irradiance[i] +=
        radiance * cap_transfer(cap, normals_[i], horizon.data(), count, config_.cap_strips);
  };
  // One compiled copy of the spans' work: TBB inlines its body into several paths, and each
  // copy may fuse multiply-adds differently (results then depend on which thread ran which span).
  auto shade_spans = [&](std::size_t s0, std::size_t s1) __attribute__((noinline)) {
    if (!sweep) {
      for (std::size_t si = s0; si < s1; ++si)
        for (int x = spans[si].x0; x < spans[si].x1; ++x) shade(x, spans[si].y);
      return;
    }
    // With the sweep, sixteen receivers at a time (cap_first_pass16): the closed cases first,
    // then the receivers that need chords gathered and passed again eight at a time
    // (cap_transfer8), wide caps with their cap_horizons samples (the middle one, tau = 0, is the
    // foot's direction: the sweep's).
    const int samples = config_.cap_horizons;
    const int middle = samples % 2 == 1 ? samples / 2 : -1;
    // Two queues, kept across the task's spans: caps the tangent plane cuts (|n.d| < radius:
    // general chords, sixteen at a time, cap_chords16) and the others (front chords or the lens,
    // eight, cap_transfer8), so that a batch runs one of the two chord kernels, not both, and is
    // partly filled only at the end (each lane's floats are the same in any batch).
    ChordQueue<CapLanes, 8> front_queue;
    ChordQueue<CapChordLanes16, 16> cut_queue;
    auto flush = [&](auto& qu) {
      constexpr int W = std::remove_reference_t<decltype(qu)>::kWidth;
      auto& batch = qu.batch;
      const int queued = qu.queued;
      batch.count = qu.varied ? samples : 1;
      for (int l = queued; l < W; ++l) {  // padding lanes repeat the first
        batch.dx[l] = batch.dx[0], batch.dy[l] = batch.dy[0], batch.dz[l] = batch.dz[0];
        batch.nx[l] = batch.nx[0], batch.ny[l] = batch.ny[0], batch.nz[l] = batch.nz[0];
        for (int k = 0; k < samples; ++k) batch.horizon[k][l] = batch.horizon[k][0];
      }
      float e[W];
      if constexpr (W == 16)
        cap_chords16(batch, radius, config_.cap_strips, e);
      else
        cap_transfer8(batch, radius, std::numeric_limits<float>::infinity(), config_.cap_strips,
                      false, e);
      for (int l = 0; l < queued; ++l)
        if (e[l] > 0) add_lit(radiance, e[l], irradiance[qu.at[l]]);
      qu.queued = 0;
      qu.varied = false;
    };
    auto push = [&](auto& qu, const CapLanes16& lanes, int l, int x, int y) {
      constexpr int W = std::remove_reference_t<decltype(qu)>::kWidth;
      const glm::vec3 d(lanes.dx[l], lanes.dy[l], lanes.dz[l]);
      auto& batch = qu.batch;
      const int q = qu.queued;
      batch.dx[q] = lanes.dx[l], batch.dy[q] = lanes.dy[l], batch.dz[q] = lanes.dz[l];
      batch.nx[q] = lanes.nx[l], batch.ny[q] = lanes.ny[l], batch.nz[q] = lanes.nz[l];
      const float swept = lanes.horizon[l];
      for (int k = 0; k < samples; ++k) batch.horizon[k][q] = swept;
      LightCap cap;
      if (radius * radius >= config_.cap_wide * config_.cap_wide * glm::dot(d, d) &&
          make_light_cap(d, radius, cap) && cap.rho >= config_.cap_wide) {
        // A wide cap the horizon passes near: the horizon may vary across it.
        const float e = detail::fast_atan(cap.sin_e / std::max(cap.cos_e, 1e-30f));
        const float half = detail::fast_asin(cap.rho);
        if (swept > e - 2 * half && swept < e + 2 * half) {
          qu.varied = true;
          for (int k = 0; k < samples; ++k)
            if (k != middle)
              batch.horizon[k][q] =
                  ray_horizon(f, height_scale_, glm::vec2(x, y), height_scale_ * f.at(x, y),
                              cap_horizon_direction(cap, k, samples), cap.plane_distance, false);
        }
      }
      qu.at[q] = static_cast<std::size_t>(y) * f.width + x;
      if (++qu.queued == W) flush(qu);
    };
    auto enqueue = [&](const CapLanes16& lanes, int l, int x, int y) {
      const glm::vec3 d(lanes.dx[l], lanes.dy[l], lanes.dz[l]);
      const glm::vec3 n(lanes.nx[l], lanes.ny[l], lanes.nz[l]);
      if (std::abs(glm::dot(n, d)) < radius)
        push(cut_queue, lanes, l, x, y);
      else
        push(front_queue, lanes, l, x, y);
    };
    for (std::size_t si = s0; si < s1; ++si) {
      const Span& span = spans[si];
      const int y = span.y;
      for (int x0 = span.x0; x0 < span.x1; x0 += 16) {
        const int n = std::min(16, span.x1 - x0);
        CapLanes16 lanes;
        if (n == 16) {
          radial_.horizons16(x0, y, lanes.horizon);
          // centre - position(x, y) (as for a span's last receivers below), in loops the
          // compiler puts on vector lanes.
          const std::size_t i0 = static_cast<std::size_t>(y) * f.width + x0;
          const float dy = centre.y - static_cast<float>(y) * f.cell_size;
          for (int l = 0; l < 16; ++l) {
            lanes.dx[l] = centre.x - static_cast<float>(x0 + l) * f.cell_size;
            lanes.dy[l] = dy;
            lanes.dz[l] = centre.z - height_scale_ * f.heights[i0 + l];
          }
          for (int l = 0; l < 16; ++l) {
            lanes.nx[l] = normals_[i0 + l].x;
            lanes.ny[l] = normals_[i0 + l].y;
            lanes.nz[l] = normals_[i0 + l].z;
          }
        } else {
          for (int l = 0; l < 16; ++l) {
            const int x = x0 + std::min(l, n - 1);  // padding lanes repeat the last receiver
            const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
            const glm::vec3 d = centre - position(x, y);
            lanes.dx[l] = d.x;
            lanes.dy[l] = d.y;
            lanes.dz[l] = d.z;
            lanes.nx[l] = normals_[i].x;
            lanes.ny[l] = normals_[i].y;
            lanes.nz[l] = normals_[i].z;
            lanes.horizon[l] = l < n ? radial_.horizon(x, y) : 0.0f;
          }
        }
        float e[16];
        const unsigned other = cap_first_pass16(lanes, radius, config_.cap_wide, e);
        glm::vec3* out = irradiance.data() + static_cast<std::size_t>(y) * f.width + x0;
        if (n == 16 && other == 0) {
          add_lit8(radiance, e, out);
          add_lit8(radiance, e + 8, out + 8);
          continue;
        }
        for (int l = 0; l < n; ++l) {
          if (other >> l & 1u)
            enqueue(lanes, l, x0 + l, y);
          else if (e[l] > 0)
            add_lit(radiance, e[l], out[l]);
        }
      }
    }
    if (front_queue.queued > 0) flush(front_queue);
    if (cut_queue.queued > 0) flush(cut_queue);
  };
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, spans.size()),
      [&](const tbb::blocked_range<std::size_t>& r) { shade_spans(r.begin(), r.end()); });
}

float disc_share_above(float above, float angular_radius) {
  if (!(angular_radius > 0)) return above > 0 ? 1.0f : 0.0f;
  const float t = std::clamp(above / angular_radius, -1.0f, 1.0f);
  return (std::acos(-t) + t * std::sqrt(1 - t * t)) * std::numbers::inv_pi_v<float>;
}

namespace {
void check_key_light(const glm::vec3& d, float angular_radius, const glm::vec3& irradiance) {
  const bool finite = std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
  if (!finite || std::abs(glm::length(d) - 1.0f) > 1e-3f || !std::isfinite(angular_radius) ||
      angular_radius < 0 || !std::isfinite(irradiance.x) || !std::isfinite(irradiance.y) ||
      !std::isfinite(irradiance.z) || irradiance.x < 0 || irradiance.y < 0 || irradiance.z < 0)
    throw std::invalid_argument(
        "key light: direction must be a finite unit vector, angular radius and irradiance "
        "finite and >= 0");
}
}  // namespace

template <int N>
void TerrainShadowing<N>::key_light_horizons(const glm::vec3& direction,
                                             std::vector<float>& horizons) const {
  if (!field_) throw std::invalid_argument("terrain shadowing: key_light_horizons before update");
  check_key_light(direction, 0.0f, glm::vec3(0.0f));
  HorizonParams p;
  p.height_scale = height_scale_;
  p.clamp_at_zero = true;  // as the environment's ([Meier13] sec. 4.2.1)
  // A light straight overhead has no azimuth; any will do (the horizon is below it anyway).
  const double phi = std::atan2(static_cast<double>(direction.y), static_cast<double>(direction.x));
  sweep_direction_horizons(*field_, p, phi, TexelRect::all(*field_), horizons);
}

namespace {
// One texel's key light: irradiance x max(0, n . direction) x the disc's share above the horizon.
struct KeyLightTexel {
  glm::vec3 direction, irradiance;
  float elevation, a;
  void add(const glm::vec3& normal, float horizon, glm::vec3& out) const {
    const float c = glm::dot(normal, direction);
    if (!(c > 0)) return;
    const float above = elevation - horizon;  // most texels see all of it or none
    const float f = above >= a ? 1.0f : (above <= -a ? 0.0f : disc_share_above(above, a));
    if (f > 0) out += irradiance * (c * f);
  }
};
}  // namespace

template <int N>
void TerrainShadowing<N>::add_key_light(const glm::vec3& direction, float angular_radius,
                                        const glm::vec3& irradiance,
                                        std::span<const float> horizons,
                                        std::vector<glm::vec3>& out) const {
  if (!field_) throw std::invalid_argument("terrain shadowing: add_key_light before update");
  out.resize(normals_.size(), glm::vec3(0.0f));
  const TexelRect all = TexelRect::all(*field_);
  add_key_light(direction, angular_radius, irradiance, horizons, out, {&all, 1});
}

template <int N>
void TerrainShadowing<N>::add_key_light(const glm::vec3& direction, float angular_radius,
                                        const glm::vec3& irradiance,
                                        std::span<const float> horizons,
                                        std::vector<glm::vec3>& out,
                                        std::span<const TexelRect> regions) const {
  if (!field_) throw std::invalid_argument("terrain shadowing: add_key_light before update");
  check_key_light(direction, angular_radius, irradiance);
  const std::size_t n = normals_.size();
  if (horizons.size() != n)
    throw std::invalid_argument("add_key_light: horizons are not one per texel");
  if (out.size() != n) throw std::invalid_argument("add_key_light: output is not one per texel");
  const KeyLightTexel k{direction, irradiance, std::asin(std::clamp(direction.z, -1.0f, 1.0f)),
                        angular_radius};
  if (k.elevation + k.a <= 0) return;  // the clamped horizon hides the whole disc everywhere
  const int w = field_->width;
  // Rows of 64 texels a task: whole regions are small (tiles), the whole field is one region.
  tbb::parallel_for(std::size_t{0}, regions.size(), [&](std::size_t j) {
    const TexelRect& r = regions[j];
    tbb::parallel_for(r.y0, r.y1, [&](int y) {
      for (int x = r.x0; x < r.x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        k.add(normals_[i], horizons[i], out[i]);
      }
    });
  });
}

template class TerrainShadowing<3>;
template class TerrainShadowing<4>;
template class TerrainShadowing<5>;
template class TerrainShadowing<6>;

}  // namespace penumbra::terrain_shadow
