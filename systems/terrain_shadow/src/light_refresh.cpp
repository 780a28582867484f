#include "penumbra/systems/terrain_shadow/light_refresh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "fast_math.h"
#include "penumbra/data/luminance.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kPi;

using data::luminance;

// Distance between two boxes (0 when they overlap).
float box_distance(const glm::vec3& lo_a, const glm::vec3& hi_a, const glm::vec3& lo_b,
                   const glm::vec3& hi_b) {
  const glm::vec3 gap = glm::max(glm::max(lo_a - hi_b, lo_b - hi_a), glm::vec3(0.0f));
  return glm::length(gap);
}
}  // namespace

float sphere_solid_angle(float radius, float distance) {
  if (distance <= radius) return 2 * kPi;
  const float s = radius / distance;
  return 2 * kPi * s * s / (1 + std::sqrt(1 - s * s));  // 2 pi (1 - cos a), without cancellation
}

float light_irradiance_bound(const LightSample& light, float distance) {
  // int V max(0, n.w) dw <= min(solid angle, pi).
  return luminance(light.radiance) * std::min(sphere_solid_angle(light.radius, distance), kPi);
}

float light_change_bound(const LightSample& before, const LightSample& after, float distance) {
  if (before.centre == after.centre && before.radius == after.radius &&
      before.radiance == after.radiance)
    return 0.0f;
  const float l_max = std::max(luminance(before.radiance), luminance(after.radiance));
  const float dl = luminance(glm::abs(after.radiance - before.radiance));
  const float ceiling = kPi * l_max;  // |E1 - E0| <= max(E0, E1) <= pi L_max
  const float r_max = std::max(before.radius, after.radius);
  const float r_min = std::min(before.radius, after.radius);
  if (distance <= r_max) return ceiling;
  const float delta = glm::length(after.centre - before.centre);
  const float a = std::asin(r_max / distance);
  const float theta = std::min(kPi, delta / distance);
  const float omega_max = sphere_solid_angle(r_max, distance);
  const float radial = omega_max - sphere_solid_angle(r_min, distance + delta);
  return std::min(ceiling, l_max * (4 * a * theta + radial) + dl * omega_max);
}

LightRefresh::LightRefresh(const LightRefreshConfig& config) : config_(config) {
  if (config.tile < 1 || !(config.tolerance >= 0) || !(config.dark_floor >= 0) ||
      !(config.budget > 0 && config.budget <= 1))
    throw std::invalid_argument(
        "light refresh: tile >= 1, tolerance >= 0, dark_floor >= 0 and budget in (0, 1] needed");
}

void LightRefresh::reset(int width, int height, const std::vector<glm::vec3>& positions) {
  if (width < 1 || height < 1 || positions.size() != static_cast<std::size_t>(width) * height)
    throw std::invalid_argument("light refresh: positions must be width x height");
  const std::vector<Tile> old = std::move(tiles_);
  const bool same_grid = width == width_ && height == height_;
  width_ = width;
  height_ = height;
  const int t = config_.tile;
  tiles_x_ = (width + t - 1) / t;
  const int tiles_y = (height + t - 1) / t;
  tiles_.assign(static_cast<std::size_t>(tiles_x_) * tiles_y, {});
  for (int ty = 0; ty < tiles_y; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      Tile& tile = tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx];
      tile.rect = {tx * t, ty * t, std::min(width, (tx + 1) * t), std::min(height, (ty + 1) * t)};
      tile.lo = glm::vec3(std::numeric_limits<float>::max());
      tile.hi = -tile.lo;
      for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
        for (int x = tile.rect.x0; x < tile.rect.x1; ++x) {
          const glm::vec3& p = positions[static_cast<std::size_t>(y) * width + x];
          tile.lo = glm::min(tile.lo, p);
          tile.hi = glm::max(tile.hi, p);
        }
      // The same grid keeps the references of the last frame (a terrain edit, say).
      if (same_grid) tile.reference = old[static_cast<std::size_t>(ty) * tiles_x_ + tx].reference;
      tile.shaded_with = kNever;
    }
  }
  snapshots_.clear();
  planned_.clear();
  rects_.clear();
  stats_.tiles = tiles_.size();
}

void LightRefresh::set_reference(const std::vector<glm::vec3>& irradiance, float scale) {
  if (irradiance.size() != static_cast<std::size_t>(width_) * height_) return;
  double sum = 0;
  texel_reference_.resize(irradiance.size());
  for (Tile& tile : tiles_) {
    float darkest = std::numeric_limits<float>::max();
    for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
      for (int x = tile.rect.x0; x < tile.rect.x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        const float e = scale * luminance(irradiance[i]);
        texel_reference_[i] = e;
        darkest = std::min(darkest, e);
        sum += e;
      }
    tile.reference = std::max(darkest, 0.0f);
  }
  mean_reference_ = static_cast<float>(std::max(sum, 0.0) / static_cast<double>(irradiance.size()));
}

const std::vector<TexelRect>& LightRefresh::plan(const std::vector<LightSample>& lights) {
  struct Candidate {
    bool never;
    float key;  // never: brightest light bound; else bound / threshold
    std::size_t tile;
  };
  std::vector<Candidate> stale;
  for (std::size_t i = 0; i < tiles_.size(); ++i) {
    const Tile& tile = tiles_[i];
    if (tile.shaded_with == kNever) {
      float brightest = 0;
      for (const LightSample& l : lights)
        brightest = std::max(brightest, light_irradiance_bound(
                                            l, box_distance(tile.lo, tile.hi, l.centre, l.centre)));
      stale.push_back({true, brightest, i});
      continue;
    }
    const std::vector<LightSample>& before = snapshots_[tile.shaded_with];
    float bound = 0;
    for (std::size_t k = 0; k < std::max(before.size(), lights.size()); ++k) {
      if (k < before.size() && k < lights.size()) {
        const glm::vec3 lo = glm::min(before[k].centre, lights[k].centre);
        const glm::vec3 hi = glm::max(before[k].centre, lights[k].centre);
        bound += light_change_bound(before[k], lights[k], box_distance(tile.lo, tile.hi, lo, hi));
      } else {
        const LightSample& l = k < before.size() ? before[k] : lights[k];
        bound += light_irradiance_bound(l, box_distance(tile.lo, tile.hi, l.centre, l.centre));
      }
    }
    const float threshold =
        config_.tolerance * std::max(tile.reference, config_.dark_floor * mean_reference_);
    if (bound <= threshold) continue;
    stale.push_back(
        {false, threshold > 0 ? bound / threshold : std::numeric_limits<float>::max(), i});
  }
  std::sort(stale.begin(), stale.end(), [](const Candidate& a, const Candidate& b) {
    if (a.never != b.never) return a.never;
    if (a.key != b.key) return a.key > b.key;
    return a.tile < b.tile;
  });
  const auto budget = static_cast<std::size_t>(
      std::ceil(config_.budget * static_cast<double>(width_) * static_cast<double>(height_)));
  planned_.clear();
  rects_.clear();
  std::size_t texels = 0;
  stats_.stale = stale.size();
  stats_.worst_deferred = 0;
  stats_.unshaded_waiting = 0;
  for (const Candidate& c : stale) {
    const TexelRect& r = tiles_[c.tile].rect;
    if (!planned_.empty() && texels + r.count() > budget) {
      if (c.never)
        ++stats_.unshaded_waiting;
      else
        stats_.worst_deferred = std::max(stats_.worst_deferred, c.key);
      continue;
    }
    texels += r.count();
    planned_.push_back(c.tile);
    rects_.push_back(r);
  }
  stats_.refreshed = planned_.size();
  planned_lights_ = lights;
  return rects_;
}

void LightRefresh::keep_previous(const std::vector<glm::vec3>& irradiance) {
  previous_.clear();
  if (irradiance.size() != static_cast<std::size_t>(width_) * height_) return;
  for (std::size_t i : planned_) {
    const TexelRect& r = tiles_[i].rect;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x)
        previous_.push_back(irradiance[static_cast<std::size_t>(y) * width_ + x]);
  }
}

void LightRefresh::commit(const std::vector<glm::vec3>* irradiance) {
  stats_.worst_observed = 0;
  stats_.observed_texels = stats_.observed_visible = 0;
  if (irradiance && !previous_.empty() && texel_reference_.size() == irradiance->size() &&
      irradiance->size() == static_cast<std::size_t>(width_) * height_) {
    // Each texel's real change against its own threshold (the plan used the tile's darkest).
    const float floor = config_.dark_floor * mean_reference_;
    std::size_t k = 0;
    for (std::size_t t : planned_) {
      const Tile& tile = tiles_[t];
      for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
        for (int x = tile.rect.x0; x < tile.rect.x1; ++x, ++k) {
          const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
          const float reference = std::max(texel_reference_[i], floor);
          const float change = std::abs(luminance((*irradiance)[i]) - luminance(previous_[k]));
          if (tile.shaded_with == kNever || !(reference > 0)) continue;
          ++stats_.observed_texels;
          stats_.observed_visible += change > config_.tolerance * reference;
          stats_.worst_observed = std::max(stats_.worst_observed, change / reference);
        }
    }
  }
  previous_.clear();
  if (planned_.empty()) return;
  snapshots_.push_back(planned_lights_);
  const auto latest = static_cast<std::uint32_t>(snapshots_.size() - 1);
  for (std::size_t i : planned_) tiles_[i].shaded_with = latest;
  planned_.clear();
  ++stats_.frames_shaded;
  // Drop the snapshots no tile refers to any more.
  std::vector<std::uint32_t> remap(snapshots_.size(), kNever);
  for (const Tile& t : tiles_)
    if (t.shaded_with != kNever) remap[t.shaded_with] = 0;
  std::uint32_t next = 0;
  for (std::size_t s = 0; s < snapshots_.size(); ++s)
    if (remap[s] == 0) {
      remap[s] = next;
      if (s != next) snapshots_[next] = std::move(snapshots_[s]);
      ++next;
    }
  snapshots_.resize(next);
  for (Tile& t : tiles_)
    if (t.shaded_with != kNever) t.shaded_with = remap[t.shaded_with];
}

}  // namespace penumbra::terrain_shadow
