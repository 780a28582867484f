#include "penumbra/systems/terrain_shadow/environment_refresh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "penumbra/data/luminance.h"

namespace penumbra::terrain_shadow {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

using data::luminance;

float angle_between(const glm::vec3& a, const glm::vec3& b) {
  // 2 asin(|a - b| / 2): accurate for small angles, where acos(a . b) is not.
  return 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(a - b)));
}

bool same_pose(const EnvironmentPose& a, const EnvironmentPose& b) {
  if (a.rotation != b.rotation || a.horizons_generation != b.horizons_generation ||
      a.keys.size() != b.keys.size())
    return false;
  for (std::size_t k = 0; k < a.keys.size(); ++k)
    if (a.keys[k].direction != b.keys[k].direction) return false;
  return true;
}

}  // namespace

float rotation_speed_bound(std::span<const float> r, std::span<const float> g,
                           std::span<const float> b) {
  const std::span<const float> rgb[3] = {r, g, b};
  const float w[3] = {0.2126f, 0.7152f, 0.0722f};
  float sum = 0.0f;
  for (int c = 0; c < 3; ++c) {
    double s = 0;
    for (std::size_t i = 0; i < rgb[c].size(); ++i) {
      const int l = static_cast<int>(std::sqrt(static_cast<double>(i)));
      const int m = static_cast<int>(i) - l * l - l;
      s += static_cast<double>(m) * m * rgb[c][i] * rgb[c][i];
    }
    sum += w[c] * static_cast<float>(std::sqrt(s));
  }
  return sum;
}

EnvironmentRefresh::EnvironmentRefresh(const EnvironmentRefreshConfig& config) : config_(config) {
  if (config_.tile < 1) throw std::invalid_argument("environment refresh: tile must be >= 1");
  if (!(config_.budget > 0 && config_.budget <= 1))
    throw std::invalid_argument("environment refresh: budget must be in (0, 1]");
}

void EnvironmentRefresh::reset(int width, int height, std::vector<float> transfer_norm) {
  if (width < 1 || height < 1 || transfer_norm.size() != static_cast<std::size_t>(width) * height)
    throw std::invalid_argument("environment refresh: transfer norms are not one per texel");
  width_ = width;
  height_ = height;
  transfer_norm_ = std::move(transfer_norm);
  const int t = config_.tile;
  tiles_x_ = (width + t - 1) / t;
  const int tiles_y = (height + t - 1) / t;
  tiles_.assign(static_cast<std::size_t>(tiles_x_) * tiles_y, Tile{});
  for (int ty = 0; ty < tiles_y; ++ty)
    for (int tx = 0; tx < tiles_x_; ++tx)
      tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx].rect = {
          tx * t, ty * t, std::min(width, (tx + 1) * t), std::min(height, (ty + 1) * t)};
  key_count_.assign(tiles_.size(), 0);
  has_last_pose_ = false;
  stats_ = {};
  stats_.tiles = tiles_.size();
}

void EnvironmentRefresh::invalidate() {
  for (Tile& t : tiles_) t.shaded = false;
  has_last_pose_ = false;
}

void EnvironmentRefresh::set_reference(const std::vector<glm::vec3>& irradiance, float scale) {
  if (irradiance.size() != transfer_norm_.size()) return;
  double mean = 0;
  for (const glm::vec3& e : irradiance) mean += luminance(e) * scale;
  const float floor = std::max(
      config_.dark_floor * static_cast<float>(mean / static_cast<double>(std::max<std::size_t>(
                                                         1, irradiance.size()))),
      std::numeric_limits<float>::min());
  for (Tile& tile : tiles_) {
    float darkest = kInf, ratio = 0.0f;
    const TexelRect& r = tile.rect;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        float e = luminance(irradiance[i]) * scale;
        e = std::isfinite(e) ? std::max(e, floor) : floor;
        darkest = std::min(darkest, e);
        ratio = std::max(ratio, transfer_norm_[i] / e);
      }
    tile.reference = darkest;
    tile.transfer_max = ratio;
  }
}

float EnvironmentRefresh::bound_over_threshold(std::size_t i, const EnvironmentPose& pose) const {
  const Tile& t = tiles_[i];
  if (!t.shaded || t.generation != pose.horizons_generation || key_count_[i] != pose.keys.size())
    return kInf;
  if (!(t.reference > 0)) return kInf;  // no reference yet: every change shows
  // The SH term per texel (transfer_max is the largest |T| / reference), the key lights' per
  // tile; both relative to the tolerance.
  float relative =
      std::abs(std::remainder(pose.rotation - t.rotation, 2.0f * std::numbers::pi_v<float>)) *
      pose.rotation_speed * t.transfer_max;
  float keys = 0.0f;
  for (std::size_t k = 0; k < pose.keys.size(); ++k) {
    const KeyLightPose& key = pose.keys[k];
    const float delta = angle_between(key.direction, key_direction_[i * max_keys_ + k]);
    if (delta == 0) continue;
    float slope = 1.0f;
    if (delta >= key_margin_[i * max_keys_ + k])
      slope +=
          key.angular_radius > 0 ? 2.0f / (std::numbers::pi_v<float> * key.angular_radius) : kInf;
    keys += key.luminance * delta * slope;
  }
  relative += keys / t.reference;
  return relative / config_.tolerance;
}

const std::vector<TexelRect>& EnvironmentRefresh::plan(const EnvironmentPose& pose,
                                                       bool unlimited) {
  planned_.clear();
  rects_.clear();
  stats_.stale = stats_.refreshed = 0;
  stats_.worst_deferred = 0.0f;
  if (tiles_.empty()) return rects_;
  const bool settle = has_last_pose_ && same_pose(pose, last_pose_);
  std::vector<std::pair<float, std::size_t>>& stale = candidates_;  // kept: no allocation a frame
  stale.clear();
  for (std::size_t i = 0; i < tiles_.size(); ++i) {
    const float b = bound_over_threshold(i, pose);
    if (b > 1.0f) {
      ++stats_.stale;
      stale.push_back({b, i});
    } else if (settle && b > 0.0f) {
      stale.push_back({b - 2.0f, i});  // after every tile over the tolerance
    }
  }
  const std::size_t budget =
      unlimited
          ? tiles_.size()
          : std::max<std::size_t>(1, static_cast<std::size_t>(config_.budget * tiles_.size()));
  const std::size_t take = std::min(budget, stale.size());
  std::partial_sort(stale.begin(), stale.begin() + static_cast<std::ptrdiff_t>(take), stale.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t j = 0; j < take; ++j) {
    planned_.push_back(stale[j].second);
    rects_.push_back(tiles_[stale[j].second].rect);
  }
  for (std::size_t j = take; j < stale.size(); ++j)
    if (std::isfinite(stale[j].first))
      stats_.worst_deferred = std::max(stats_.worst_deferred, stale[j].first);
  stats_.refreshed = take;
  last_pose_ = pose;
  for (KeyLightPose& k : last_pose_.keys) k.horizons = {};  // only directions are compared
  has_last_pose_ = true;
  return rects_;
}

void EnvironmentRefresh::commit(const EnvironmentPose& pose,
                                const std::vector<glm::vec3>& normals) {
  if (pose.keys.size() > max_keys_) {  // widen the per-tile key arrays
    const std::size_t old = max_keys_;
    max_keys_ = pose.keys.size();
    std::vector<glm::vec3> dirs(tiles_.size() * max_keys_);
    std::vector<float> margins(tiles_.size() * max_keys_, -kInf);
    for (std::size_t i = 0; i < tiles_.size(); ++i)
      for (std::size_t k = 0; k < old; ++k) {
        dirs[i * max_keys_ + k] = key_direction_[i * old + k];
        margins[i * max_keys_ + k] = key_margin_[i * old + k];
      }
    key_direction_ = std::move(dirs);
    key_margin_ = std::move(margins);
  }
  for (std::size_t i : planned_) {
    Tile& t = tiles_[i];
    t.shaded = true;
    t.rotation = pose.rotation;
    t.generation = pose.horizons_generation;
    key_count_[i] = pose.keys.size();
    for (std::size_t k = 0; k < pose.keys.size(); ++k) {
      const KeyLightPose& key = pose.keys[k];
      const float elevation = std::asin(std::clamp(key.direction.z, -1.0f, 1.0f));
      float margin = kInf;
      const TexelRect& r = t.rect;
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const std::size_t j = static_cast<std::size_t>(y) * width_ + x;
          if (j >= normals.size() || j >= key.horizons.size()) {
            margin = -kInf;  // nothing to go by: every turn may show
            continue;
          }
          if (!(glm::dot(normals[j], key.direction) > 0)) continue;
          margin = std::min(margin, std::abs(elevation - key.horizons[j]) - key.angular_radius);
        }
      key_direction_[i * max_keys_ + k] = key.direction;
      key_margin_[i * max_keys_ + k] = margin;
    }
  }
}

}  // namespace penumbra::terrain_shadow
