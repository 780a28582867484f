#include "penumbra/reference/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra::reference {
namespace {

[[noreturn]] void fail(const data::EnvironmentMap& map, const std::string& why) {
  throw std::invalid_argument("reference: environment map \"" + map.source + "\": " + why);
}

// Index of the interval [cdf[i], cdf[i+1]) holding u (cdf increasing from 0 to 1, u in [0,1)),
// searched in [lo, hi], never an empty interval; and u's position inside it, in [0, 1).
int invert(const double* cdf, int lo, int hi, double u, double& remainder) {
  const double* it = std::upper_bound(cdf + lo, cdf + hi + 1, u);
  const int i = std::clamp(static_cast<int>(it - cdf) - 1, lo, hi);
  const double width = cdf[i + 1] - cdf[i];
  remainder = width > 0 ? std::clamp((u - cdf[i]) / width, 0.0, 0x1.fffffffffffffp-1) : 0.0;
  return i;
}

}  // namespace

EnvironmentSampler::EnvironmentSampler(const data::EnvironmentMap& map, float rotation_z)
    : width_(map.width), height_(map.height) {
  if (map.width <= 0 || map.height <= 0) {
    fail(map, "size " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                  " is not positive");
  }
  const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
  if (map.rgb.size() != 3 * texels) {
    fail(map, "rgb holds " + std::to_string(map.rgb.size()) + " floats, expected " +
                  std::to_string(3 * texels));
  }
  if (!std::isfinite(rotation_z)) fail(map, "rotation_z is not finite");
  for (std::size_t i = 0; i < map.rgb.size(); ++i) {
    if (!std::isfinite(map.rgb[i]) || map.rgb[i] < 0) {
      const std::size_t t = i / 3;
      fail(map, "texel (" + std::to_string(t % map.width) + ", " + std::to_string(t / map.width) +
                    ") channel " + std::to_string(i % 3) + " = " + std::to_string(map.rgb[i]) +
                    " (radiance must be finite and >= 0)");
    }
  }
  cos_rot_ = std::cos(rotation_z);
  sin_rot_ = std::sin(rotation_z);

  z_edge_.resize(height_ + 1);
  for (int y = 0; y <= height_; ++y) z_edge_[y] = std::cos(std::numbers::pi * y / height_);
  z_edge_[0] = 1;
  z_edge_[height_] = -1;

  // Conditional CDFs over columns (luminance), marginal over rows (luminance x solid angle).
  texels_.resize(texels);
  guide_size_ = std::max(1, width_ / 4);
  col_guide_.assign(static_cast<std::size_t>(height_) * (guide_size_ + 1), 0);
  col_cdf_.assign(static_cast<std::size_t>(height_) * (width_ + 1), 0.0);
  row_cdf_.assign(height_ + 1, 0.0);
  std::vector<double> lum(texels);
  for (int y = 0; y < height_; ++y) {
    double* cdf = &col_cdf_[static_cast<std::size_t>(y) * (width_ + 1)];
    for (int x = 0; x < width_; ++x) {
      const float* t = map.texel(x, y);
      const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
      lum[i] = luminance({t[0], t[1], t[2]});
      texels_[i] = {t[0], t[1], t[2], 0.0f};
      cdf[x + 1] = cdf[x] + lum[i];
    }
    const double row_sum = cdf[width_];
    for (int x = 1; x <= width_; ++x) cdf[x] = row_sum > 0 ? cdf[x] / row_sum : double(x) / width_;
    cdf[width_] = 1;
    // Guide table (Chen and Asau 1974): the interval holding u = k / G, so that a search only
    // spans the few intervals between two guide entries.
    std::uint32_t* guide = &col_guide_[static_cast<std::size_t>(y) * (guide_size_ + 1)];
    int i = 0;
    for (int k = 0; k <= guide_size_; ++k) {
      const double u = static_cast<double>(k) / guide_size_;
      while (i < width_ - 1 && cdf[i + 1] <= u) ++i;
      guide[k] = static_cast<std::uint32_t>(i);
    }
    const double solid_angle = 2 * std::numbers::pi / width_ * (z_edge_[y] - z_edge_[y + 1]);
    row_cdf_[y + 1] = row_cdf_[y] + row_sum * solid_angle;
  }
  total_ = row_cdf_[height_];
  if (total_ > 0) {
    for (int y = 1; y <= height_; ++y) row_cdf_[y] /= total_;
    row_cdf_[height_] = 1;
    for (std::size_t i = 0; i < texels; ++i) texels_[i].pdf = static_cast<float>(lum[i] / total_);
  }
}

std::size_t EnvironmentSampler::texel_index(const glm::vec3& dir) const {
  // World to map frame: rotate by -rotation_z.
  const float mx = cos_rot_ * dir.x + sin_rot_ * dir.y;
  const float my = -sin_rot_ * dir.x + cos_rot_ * dir.y;
  float phi = std::atan2(my, mx);
  if (phi < 0) phi += 2 * std::numbers::pi_v<float>;
  const float theta = std::acos(std::clamp(dir.z, -1.0f, 1.0f));
  const int x = std::clamp(static_cast<int>(phi * (0.5f * std::numbers::inv_pi_v<float>)*width_), 0,
                           width_ - 1);
  const int y =
      std::clamp(static_cast<int>(theta * std::numbers::inv_pi_v<float> * height_), 0, height_ - 1);
  return static_cast<std::size_t>(y) * width_ + x;
}

EnvironmentSampler::Sample EnvironmentSampler::sample(glm::dvec2 u) const {
  double ry = 0, rx = 0;
  const int y = invert(row_cdf_.data(), 0, height_ - 1, u.y, ry);
  const std::uint32_t* guide = &col_guide_[static_cast<std::size_t>(y) * (guide_size_ + 1)];
  const int k = std::min(static_cast<int>(u.x * guide_size_), guide_size_ - 1);
  const int x = invert(&col_cdf_[static_cast<std::size_t>(y) * (width_ + 1)],
                       static_cast<int>(guide[k]), static_cast<int>(guide[k + 1]), u.x, rx);
  // Uniform in solid angle inside the texel: z uniform between the row's edges, phi uniform.
  const double z = z_edge_[y] + ry * (z_edge_[y + 1] - z_edge_[y]);
  const float r = static_cast<float>(std::sqrt(std::max(0.0, (1 - z) * (1 + z))));
  const float phi = static_cast<float>(2 * std::numbers::pi * (x + rx) / width_);
  const float mx = r * std::cos(phi), my = r * std::sin(phi);
  const Texel& t = texels_[static_cast<std::size_t>(y) * width_ + x];
  Sample s;
  s.dir = {cos_rot_ * mx - sin_rot_ * my, sin_rot_ * mx + cos_rot_ * my, static_cast<float>(z)};
  s.radiance = {t.r, t.g, t.b};
  s.pdf = t.pdf;
  return s;
}

}  // namespace penumbra::reference
