#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
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

namespace {

constexpr float kTwoPi = 2 * std::numbers::pi_v<float>;

TerrainShadowConfig checked(const TerrainShadowConfig& c) {
  if (c.light_method == HorizonMethod::kSweep)
    throw std::invalid_argument(
        "terrain shadow config: local lights need a distance limit, which the sweep lacks "
        "(use march or brute_force)");
  if (c.azimuths < 3 || c.light_azimuths < 3)
    throw std::invalid_argument("terrain shadow config: at least 3 azimuths needed");
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
void compute_horizons(HorizonMethod method, const assets::HeightField& f,
                      const HeightPyramid& pyramid, const HorizonParams& p,
                      const MarchParams& march, const TexelRect& region, HorizonGrid& out) {
  switch (method) {
    case HorizonMethod::kSweep:
      sweep_horizons(f, p, region, out);
      break;
    case HorizonMethod::kMarch:
      march_horizons(pyramid, p, march, region, out);
      break;
    case HorizonMethod::kBruteForce:
      brute_force_horizons(f, p, region, out);
      break;
  }
}

}  // namespace

template <int N>
TerrainShadowing<N>::TerrainShadowing(const TerrainShadowConfig& config)
    : config_(checked(config)),
      hemisphere_(config.azimuths, WedgeDomain::kHemisphere, config.table_resolution),
      sphere_(config.light_azimuths, WedgeDomain::kSphere, config.table_resolution) {}

template <int N>
glm::vec3 TerrainShadowing<N>::position(int x, int y) const {
  return {x * field_->cell_size, y * field_->cell_size, height_scale_ * field_->at(x, y)};
}

template <int N>
void TerrainShadowing<N>::compute_normals(const TexelRect& r) {
  const assets::HeightField& f = *field_;
  // Central differences, one-sided at the border (as reference::height_field_receivers).
  tbb::parallel_for(r.y0, r.y1, [&](int y) {
    for (int x = r.x0; x < r.x1; ++x) {
      const int xa = std::max(x - 1, 0), xb = std::min(x + 1, f.width - 1);
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, f.height - 1);
      const float dx = height_scale_ * (f.at(xb, y) - f.at(xa, y)) / ((xb - xa) * f.cell_size);
      const float dy = height_scale_ * (f.at(x, yb) - f.at(x, ya)) / ((yb - ya) * f.cell_size);
      const glm::vec3 n(-dx, -dy, 1.0f);
      normals_[static_cast<std::size_t>(y) * f.width + x] = n / std::sqrt(glm::dot(n, n));
    }
  });
}

template <int N>
void TerrainShadowing<N>::compute_transfer_rows(const std::vector<unsigned char>* mask) {
  const int w = field_->width;
  tbb::parallel_for(0, field_->height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (mask && !(*mask)[i]) continue;
      // 000 eq. 4.19 then 4.21.
      transfer_[i] =
          diffuse_transfer<N>(hemisphere_.visibility(horizons_.texel(x, y)), normals_[i]);
    }
  });
}

template <int N>
UpdateStats TerrainShadowing<N>::update(std::shared_ptr<const assets::HeightField> field,
                                        float height_scale) {
  if (!field) throw std::invalid_argument("terrain shadowing: no height field");
  const HorizonParams p = env_params(config_, height_scale);
  validate_horizon_input(*field, p, TexelRect::all(*field));
  field_ = std::move(field);
  height_scale_ = height_scale;
  const assets::HeightField& f = *field_;
  const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
  normals_.resize(n);
  transfer_.resize(n);
  compute_normals(TexelRect::all(f));
  pyramid_valid_ = false;
  if (config_.method == HorizonMethod::kMarch || config_.light_method == HorizonMethod::kMarch) {
    pyramid_.build(f, height_scale, config_.pyramid);
    pyramid_valid_ = true;
  }
  compute_horizons(config_.method, f, pyramid_, p, config_.march, TexelRect::all(f), horizons_);
  compute_transfer_rows(nullptr);
  return {true, n * config_.azimuths, n};
}

template <int N>
UpdateStats TerrainShadowing<N>::update_edit(std::shared_ptr<const assets::HeightField> field,
                                             float height_scale, TexelRect edited) {
  if (!field_ || !field || field->width != field_->width || field->height != field_->height ||
      height_scale != height_scale_ || config_.method != HorizonMethod::kSweep)
    return update(std::move(field), height_scale);
  const HorizonParams p = env_params(config_, height_scale);
  edited.x0 = std::max(edited.x0, 0);
  edited.y0 = std::max(edited.y0, 0);
  edited.x1 = std::min(edited.x1, field->width);
  edited.y1 = std::min(edited.y1, field->height);
  validate_horizon_input(*field, p, edited);
  const std::shared_ptr<const assets::HeightField> old = field_;
  field_ = std::move(field);
  if (edited.empty()) return {};
  const assets::HeightField& f = *field_;
  const int w = f.width, h = f.height;

  // Line samples interpolate between neighbouring rows, so the edit reaches one texel further;
  // normals use central differences: also one further.
  const TexelRect e{std::max(edited.x0 - 1, 0), std::max(edited.y0 - 1, 0),
                    std::min(edited.x1 + 1, w), std::min(edited.y1 + 1, h)};
  compute_normals(e);
  if (pyramid_valid_) pyramid_.build(f, height_scale, config_.pyramid);
  float top = -std::numeric_limits<float>::infinity();
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) top = std::max({top, old->at(x, y), f.at(x, y)});
  top *= height_scale;

  // A (texel, azimuth) pair can change only if its ray crosses the edited box (widened by a
  // cell for the line either side) and the box's highest point, old or new, could reach its
  // horizon: (top - h) / distance >= tan(horizon). Those pairs are recomputed exactly as the
  // sweep would (sweep_line_horizon), so the result equals a full sweep.
  std::vector<unsigned char> changed(static_cast<std::size_t>(w) * h, 0);
  std::vector<std::size_t> pairs_per_row(h, 0);
  const float cs = f.cell_size;
  const float bx0 = (e.x0 - 1) * cs, bx1 = e.x1 * cs, by0 = (e.y0 - 1) * cs, by1 = e.y1 * cs;
  const int n_phi = config_.azimuths;
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      float* angles = horizons_.texel(x, y);
      const float px = x * cs, py = y * cs;
      const bool inside = px >= bx0 && px <= bx1 && py >= by0 && py <= by1;
      if (inside) changed[i] = 1;  // its own height or normal may have changed
      float low = f.at(x, y);
      for (int yy = std::max(y - 1, 0); yy <= std::min(y + 1, h - 1); ++yy)
        low = std::min(
            {low, f.at(x, yy), f.at(std::max(x - 1, 0), yy), f.at(std::min(x + 1, w - 1), yy)});
      low *= height_scale;
      const float dx = std::max({bx0 - px, 0.0f, px - bx1}),
                  dy = std::max({by0 - py, 0.0f, py - by1});
      const float dist = std::sqrt(dx * dx + dy * dy);
      // Azimuth interval of the box seen from the texel.
      float a_min = 0, a_max = kTwoPi;
      if (!inside) {
        const float cx[4] = {bx0, bx1, bx0, bx1}, cy[4] = {by0, by0, by1, by1};
        const float centre = std::atan2((by0 + by1) / 2 - py, (bx0 + bx1) / 2 - px);
        a_min = a_max = 0;
        for (int c = 0; c < 4; ++c) {
          float d = std::atan2(cy[c] - py, cx[c] - px) - centre;
          d = std::remainder(d, kTwoPi);
          a_min = std::min(a_min, d);
          a_max = std::max(a_max, d);
        }
        a_min += centre;
        a_max += centre;
      }
      const float step = kTwoPi / n_phi;
      const int k0 = static_cast<int>(std::floor(a_min / step)) - 1;
      const int k1 = static_cast<int>(std::ceil(a_max / step)) + 1;
      std::size_t pairs = 0;
      for (int kk = k0; kk <= k1 && kk < k0 + n_phi; ++kk) {
        const int k = ((kk % n_phi) + n_phi) % n_phi;
        if (!inside && (dist <= 0 || (top - low) / dist < std::tan(angles[k]) - 1e-6f)) continue;
        const float a = sweep_line_horizon(f, p, x, y, k);
        ++pairs;
        if (a != angles[k]) {
          angles[k] = a;
          changed[i] = 1;
        }
      }
      pairs_per_row[y] += pairs;
    }
  });
  UpdateStats stats;
  for (std::size_t c : pairs_per_row) stats.horizon_pairs += c;
  for (unsigned char c : changed) stats.transfer_texels += c;
  compute_transfer_rows(&changed);
  return stats;
}

template <int N>
void TerrainShadowing<N>::shade_environment(const sh::CoeffsRgb<N>& radiance,
                                            std::vector<glm::vec3>& irradiance) const {
  irradiance.resize(transfer_.size());
  tbb::parallel_for(std::size_t{0}, transfer_.size(), std::size_t{1024}, [&](std::size_t i0) {
    const std::size_t i1 = std::min(i0 + 1024, transfer_.size());
    for (std::size_t i = i0; i < i1; ++i)  // 000 eq. 4.21
      irradiance[i] = {sh::dot<N>(radiance[0], transfer_[i]), sh::dot<N>(radiance[1], transfer_[i]),
                       sh::dot<N>(radiance[2], transfer_[i])};
  });
}

template <int N>
void TerrainShadowing<N>::add_spherical_light(const glm::vec3& centre, float radius,
                                              const glm::vec3& radiance,
                                              std::vector<glm::vec3>& irradiance) {
  if (!field_) throw std::invalid_argument("terrain shadowing: add_spherical_light before update");
  if (!(std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z)) ||
      !std::isfinite(radius) || radius < 0 || !std::isfinite(radiance.x) ||
      !std::isfinite(radiance.y) || !std::isfinite(radiance.z) || radiance.x < 0 ||
      radiance.y < 0 || radiance.z < 0)
    throw std::invalid_argument(
        "spherical light: centre, radius and radiance must be finite, radius and radiance >= 0");
  const assets::HeightField& f = *field_;
  irradiance.resize(static_cast<std::size_t>(f.width) * f.height, glm::vec3(0.0f));
  if (radius == 0) return;
  HorizonParams p;
  p.azimuths = config_.light_azimuths;
  p.height_scale = height_scale_;
  p.clamp_at_zero = false;
  p.limit_to_point = glm::vec2(centre.x, centre.y);
  if (light_horizons_.width != f.width || light_horizons_.height != f.height ||
      light_horizons_.azimuths != p.azimuths)
    light_horizons_.resize(f.width, f.height, p.azimuths);
  tbb::parallel_for(0, f.height, [&](int y) {
    const TexelRect row{0, y, f.width, y + 1};
    bool any = false;
    for (int x = 0; x < f.width && !any; ++x) {
      const glm::vec3 d = centre - position(x, y);
      any = glm::dot(d, d) > radius * radius &&
            glm::dot(d, normals_[static_cast<std::size_t>(y) * f.width + x]) > -radius;
    }
    if (!any) return;
    // 000 eq. 4.22-4.25 (row by row: rows are the parallel tiles).
    if (config_.light_method == HorizonMethod::kMarch)
      march_horizons(pyramid_, p, config_.march, row, light_horizons_);
    else
      for (int x = 0; x < f.width; ++x)
        for (int k = 0; k < p.azimuths; ++k)
          light_horizons_.texel(x, y)[k] = ray_horizon(
              f, height_scale_, glm::vec2(x, y), height_scale_ * f.at(x, y),
              static_cast<float>(2.0 * std::numbers::pi * k / p.azimuths),
              glm::length(glm::vec2(centre.x, centre.y) - glm::vec2(x, y) * f.cell_size), false);
    for (int x = 0; x < f.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
      const glm::vec3 d = centre - position(x, y);
      if (glm::dot(d, d) <= radius * radius || glm::dot(d, normals_[i]) <= -radius) continue;
      // 000 eq. 4.26-4.29.
      const sh::Coeffs<N> t =
          diffuse_transfer<N>(sphere_.visibility(light_horizons_.texel(x, y)), normals_[i]);
      const float e = sh::dot<N>(spherical_light_radiance<N>(d, radius), t);
      irradiance[i] += radiance * std::max(e, 0.0f);
    }
  });
}

template class TerrainShadowing<3>;
template class TerrainShadowing<4>;
template class TerrainShadowing<5>;

}  // namespace penumbra::terrain_shadow
