#include "penumbra/systems/environment/light_source_detection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "penumbra/sh/projection.h"
#include "penumbra/systems/environment/direction_kmeans.h"
#include "penumbra/systems/environment/environment_prefilter.h"

namespace penumbra::environment {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_settings(const DetectionSettings& s) {
  auto fail = [](const std::string& field, const std::string& why) {
    throw std::invalid_argument("DetectionSettings::" + field + " " + why);
  };
  if (s.source_count < 0 || s.source_count > kMaxSources)
    fail("source_count", "= " + std::to_string(s.source_count) + " is outside [0, " +
                             std::to_string(kMaxSources) + "]");
  if (s.prefilter_radius < 0)
    fail("prefilter_radius", "= " + std::to_string(s.prefilter_radius) + " is negative");
  if (!(s.light_percentile > 0.0f && s.light_percentile < 100.0f))
    fail("light_percentile", "= " + std::to_string(s.light_percentile) + " is outside (0, 100)");
  if (!(s.halo_percentile > 0.0f && s.halo_percentile <= s.light_percentile))
    fail("halo_percentile",
         "= " + std::to_string(s.halo_percentile) + " is outside (0, light_percentile]");
  if (s.min_clusters < 1)
    fail("min_clusters", "= " + std::to_string(s.min_clusters) + " is below 1");
  if (!(s.radius_sigmas > 0.0f) || !std::isfinite(s.radius_sigmas))
    fail("radius_sigmas", "= " + std::to_string(s.radius_sigmas) + " is not positive");
  if (!(s.core_fraction >= 0.0f && s.core_fraction <= 1.0f))
    fail("core_fraction", "= " + std::to_string(s.core_fraction) + " is outside [0, 1]");
  if (s.max_iterations < 1)
    fail("max_iterations", "= " + std::to_string(s.max_iterations) + " is below 1");
  if (!(s.min_contrast >= 0.0f) || !std::isfinite(s.min_contrast))
    fail("min_contrast", "= " + std::to_string(s.min_contrast) + " is negative or not finite");
}

// The values at two percentiles of `values` (all >= 0): by texel count (003) or by solid angle
// (the share of the sphere, not of the texels, below the value). The nearest rank of a sort,
// found without sorting everything: a histogram over the floats' top 16 bits (ordered like
// non-negative values), then a sort of the one bucket holding each rank.
void percentile_values(const std::vector<float>& values, const std::vector<float>& row_omega,
                       int width, bool by_solid_angle, float p_light, float p_halo, float& light,
                       float& halo) {
  const auto row_width = static_cast<std::size_t>(width);
  auto weight = [&](std::size_t i) { return by_solid_angle ? row_omega[i / row_width] : 1.0f; };
  auto bucket = [](float v) {
    std::uint32_t bits = 0;
    if (v > 0.0f) std::memcpy(&bits, &v, sizeof bits);  // -0 and 0 in bucket 0
    return bits >> 16;
  };
  std::vector<double> hist(std::size_t{1} << 16, 0.0);
  double total = 0;
  float max_value = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float w = weight(i);
    hist[bucket(values[i])] += w;
    total += w;
    max_value = std::max(max_value, values[i]);
  }
  auto at = [&](float percentile) {
    const double want = total * percentile / 100.0;
    double acc = 0;
    std::size_t b = 0;
    for (; b < hist.size(); ++b) {
      if (acc + hist[b] >= want) break;
      acc += hist[b];
    }
    if (b == hist.size()) return max_value;
    std::vector<std::pair<float, float>> in;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (bucket(values[i]) == b) in.emplace_back(values[i], weight(i));
    std::sort(in.begin(), in.end());
    for (const auto& [value, w] : in) {
      acc += w;
      if (acc >= want) return value;
    }
    return in.empty() ? max_value : in.back().first;
  };
  light = at(p_light);
  halo = at(p_halo);
}

}  // namespace

void azimuth_elevation(const glm::vec3& d, float& azimuth_deg, float& elevation_deg) {
  double az = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x)) * 180.0 / kPi;
  if (az < 0) az += 360.0;
  if (az >= 360.0) az -= 360.0;
  azimuth_deg = static_cast<float>(az);
  elevation_deg =
      static_cast<float>(std::asin(std::clamp(static_cast<double>(d.z), -1.0, 1.0)) * 180.0 / kPi);
}

LightSourceDetection detect_light_sources(const data::EnvironmentMap& map,
                                          const DetectionSettings& settings) {
  const auto t0 = std::chrono::steady_clock::now();
  check_environment_map(map);
  check_settings(settings);
  const int w = map.width, h = map.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  LightSourceDetection out;
  out.width = w;
  out.height = h;
  auto finish = [&]() {
    out.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };

  // [Ambrosj16] eq. 3.1 luminance; sec. 5.1.1 Gaussian prefilter (radius clamped to the map).
  const std::vector<float> lum = luminance_image(map);
  const int radius = std::min(settings.prefilter_radius, (w - 1) / 2);
  const std::vector<float> blurred = gaussian_prefilter(lum, w, h, radius);
  std::vector<float> row_omega(static_cast<std::size_t>(h));
  for (int y = 0; y < h; ++y)
    row_omega[static_cast<std::size_t>(y)] = sh::equirect_texel_solid_angle(y, w, h);
  auto omega = [&](std::size_t i) { return row_omega[i / static_cast<std::size_t>(w)]; };
  auto direction = [&](std::size_t i) {
    const auto x = static_cast<float>(i % static_cast<std::size_t>(w));
    const auto y = static_cast<float>(i / static_cast<std::size_t>(w));
    return sh::equirect_direction((x + 0.5f) / static_cast<float>(w),
                                  (y + 0.5f) / static_cast<float>(h));  // eq. 2.4-2.8, z-up
  };

  double blurred_energy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out.total_energy += static_cast<double>(lum[i]) * omega(i);
    blurred_energy += static_cast<double>(blurred[i]) * omega(i);
  }
  out.mean_luminance = blurred_energy / (4.0 * kPi);
  if (settings.source_count == 0) return finish();
  if (!(out.total_energy > 0.0)) {
    out.stop = "the map is black (no luminance)";
    return finish();
  }

  // Percentile thresholds and the datasets D^l, D^h (Algorithm 1). Strictly above the
  // threshold, so a flat background that fills the percentile is not light.
  percentile_values(
      blurred, row_omega, w, settings.percentile_weight == PercentileWeight::kSolidAngle,
      settings.light_percentile, settings.halo_percentile, out.light_threshold, out.halo_threshold);
  std::vector<std::uint32_t> light, halo;
  for (std::size_t i = 0; i < n; ++i) {
    if (blurred[i] > out.halo_threshold) halo.push_back(static_cast<std::uint32_t>(i));
    if (blurred[i] > out.light_threshold) light.push_back(static_cast<std::uint32_t>(i));
  }
  out.light_texels = static_cast<int>(light.size());
  out.halo_texels = static_cast<int>(halo.size());

  const bool unit = settings.cluster_space == ClusterSpace::kUnitDirection;
  auto point = [&](std::size_t i) {
    return unit ? direction(i)
                : glm::vec3(static_cast<float>(i % static_cast<std::size_t>(w)),
                            static_cast<float>(i / static_cast<std::size_t>(w)), 0.0f);
  };
  const float texel_angle = static_cast<float>(kPi) / static_cast<float>(h);

  std::vector<int> owner(n, -1);    // source that removed the texel
  std::vector<char> taken(n, 0);    // removed from D^l
  std::vector<char> in_halo(n, 0);  // scratch for the connected halo
  double remaining_blurred = blurred_energy;
  int k = std::max(settings.min_clusters, settings.source_count);
  while (static_cast<int>(out.sources.size()) < settings.source_count) {
    std::vector<std::uint32_t> set;
    for (std::uint32_t i : light)
      if (!taken[i] && owner[i] < 0) set.push_back(i);
    if (set.empty()) {
      out.stop = "no bright texels left (D^l is empty)";
      break;
    }
    std::vector<glm::vec3> pts(set.size());
    std::vector<float> wts(set.size());
    std::size_t first = 0;
    for (std::size_t j = 0; j < set.size(); ++j) {
      pts[j] = point(set[j]);
      wts[j] = unit ? omega(set[j]) : 1.0f;
      if (blurred[set[j]] > blurred[set[first]]) first = j;
    }
    const KMeansResult km = kmeans(pts, wts, std::max(1, k), first, settings.max_iterations);

    // Magnitude of each cluster: the (weighted) mean luminance of its texels; take the largest.
    std::vector<double> mag(km.means.size(), 0.0);
    for (std::size_t j = 0; j < set.size(); ++j)
      mag[static_cast<std::size_t>(km.assignment[j])] +=
          static_cast<double>(wts[j]) * blurred[set[j]];
    std::size_t chosen = 0;
    for (std::size_t c = 0; c < mag.size(); ++c) {
      mag[c] = km.weights[c] > 0 ? mag[c] / km.weights[c] : 0.0;
      if (mag[c] > mag[chosen]) chosen = c;
    }
    const double remaining_mean = remaining_blurred / (4.0 * kPi);
    const double contrast = remaining_mean > 0 ? mag[chosen] / remaining_mean : 0.0;
    if (contrast < settings.min_contrast) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "the brightest remaining cluster is %.2f x the map's mean luminance, below "
                    "min_contrast %.2f",
                    contrast, static_cast<double>(settings.min_contrast));
      out.stop = buf;
      break;
    }

    DetectedSource src;
    src.clusters = static_cast<int>(km.means.size());
    src.peak_contrast = static_cast<float>(contrast);
    const glm::vec3 mean = km.means[chosen];
    if (unit) {
      const float len = glm::length(mean);
      src.direction = len > 1e-6f ? mean / len : pts[first];
    } else {
      src.direction = sh::equirect_direction((mean.x + 0.5f) / static_cast<float>(w),
                                             (mean.y + 0.5f) / static_cast<float>(h));
    }

    // The halo: D^h texels still in the map, either whose nearest mean is the chosen one (003)
    // or connected to the chosen cluster through D^h (rows wrap at the seam, the first and last
    // rows across the pole).
    std::vector<std::uint32_t> mine;
    if (settings.halo_set == HaloSet::kNearestCentroid) {
      for (std::uint32_t i : halo) {
        if (owner[i] >= 0) continue;
        const glm::vec3 p = point(i);
        std::size_t best = 0;
        float best_d = 0;
        for (std::size_t c = 0; c < km.means.size(); ++c) {
          const glm::vec3 d = p - km.means[c];
          const float dd = glm::dot(d, d);
          if (c == 0 || dd < best_d) {
            best_d = dd;
            best = c;
          }
        }
        if (best == chosen) mine.push_back(i);
      }
    } else {
      std::vector<std::uint32_t> stack;
      for (std::size_t j = 0; j < set.size(); ++j)
        if (static_cast<std::size_t>(km.assignment[j]) == chosen && !in_halo[set[j]]) {
          in_halo[set[j]] = 1;
          stack.push_back(set[j]);
        }
      auto visit = [&](std::size_t x, std::size_t y) {
        const std::size_t i = y * static_cast<std::size_t>(w) + x;
        if (in_halo[i] || owner[i] >= 0 || !(blurred[i] > out.halo_threshold)) return;
        in_halo[i] = 1;
        stack.push_back(static_cast<std::uint32_t>(i));
      };
      const auto uw = static_cast<std::size_t>(w), uh = static_cast<std::size_t>(h);
      while (!stack.empty()) {
        const std::uint32_t i = stack.back();
        stack.pop_back();
        mine.push_back(i);
        const std::size_t x = i % uw, y = i / uw;
        visit((x + 1) % uw, y);
        visit((x + uw - 1) % uw, y);
        visit(x, y > 0 ? y - 1 : 0);
        visit(x, y + 1 < uh ? y + 1 : y);
        if (y == 0 || y + 1 == uh) visit((x + uw / 2) % uw, y);  // across the pole
      }
      std::sort(mine.begin(), mine.end());
      for (std::uint32_t i : mine) in_halo[i] = 0;
    }
    // Radius: radius_sigmas x the largest standard deviation of the halo texels (003: 3 max(
    // sigma_x, sigma_y)); on directions, in the tangent plane at the source's direction.
    float radius_out = 0;  // angular radius (radians), or pixels in 003's space
    // kConnected: the deviation is measured on the halo's core (texels at least core_fraction of
    // its peak: the half-maximum region by default), so a glow around the source does not
    // widen it.
    float peak = 0;
    for (std::uint32_t i : mine) peak = std::max(peak, blurred[i]);
    const float core =
        settings.halo_set == HaloSet::kConnected ? settings.core_fraction * peak : -1.0f;
    std::vector<std::uint32_t> core_texels;
    for (std::uint32_t i : mine)
      if (blurred[i] >= core) core_texels.push_back(i);
    if (core_texels.empty()) core_texels = mine;
    if (settings.halo_set == HaloSet::kConnected && unit) {
      // The direction from the core's luminous centroid, not the cluster's mean: k-means splits
      // one blob among several clusters, whose means are off its centre by up to a cluster.
      glm::dvec3 sum(0.0);
      for (std::uint32_t i : core_texels)
        sum += static_cast<double>(omega(i)) * blurred[i] * glm::dvec3(direction(i));
      if (glm::length(sum) > 0) src.direction = glm::vec3(glm::normalize(sum));
    }
    if (unit) {
      const glm::vec3 dz = src.direction;
      const glm::vec3 ref = std::abs(dz.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
      const glm::vec3 ex = glm::normalize(glm::cross(ref, dz)), ey = glm::cross(dz, ex);
      double sw = 0, sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      for (std::uint32_t i : core_texels) {
        const glm::vec3 d = direction(i);
        const float c = std::clamp(glm::dot(d, dz), -1.0f, 1.0f);
        const float ang = std::acos(c);
        const glm::vec2 t(glm::dot(d, ex), glm::dot(d, ey));
        const float tl = std::sqrt(t.x * t.x + t.y * t.y);
        const double a = tl > 0 ? ang * t.x / tl : 0.0, b = tl > 0 ? ang * t.y / tl : 0.0;
        const double wi = settings.radius_weight == RadiusWeight::kLuminance
                              ? static_cast<double>(omega(i)) * blurred[i]
                              : static_cast<double>(omega(i));
        sw += wi;
        sa += wi * a;
        sb += wi * b;
        saa += wi * a * a;
        sbb += wi * b * b;
        sab += wi * a * b;
      }
      double sigma = 0;
      if (sw > 0) {
        const double ma = sa / sw, mb = sb / sw;
        const double caa = saa / sw - ma * ma, cbb = sbb / sw - mb * mb, cab = sab / sw - ma * mb;
        const double tr = 0.5 * (caa + cbb);
        const double lmax =
            tr + std::sqrt(std::max(0.0, 0.25 * (caa - cbb) * (caa - cbb) + cab * cab));
        sigma = std::sqrt(std::max(0.0, lmax));
      }
      radius_out = std::max(texel_angle, static_cast<float>(settings.radius_sigmas * sigma));
      src.angular_radius = radius_out;
    } else {
      double sx = 0, sy = 0, sxx = 0, syy = 0;
      for (std::uint32_t i : core_texels) {
        const glm::vec3 p = point(i);
        sx += p.x;
        sy += p.y;
        sxx += static_cast<double>(p.x) * p.x;
        syy += static_cast<double>(p.y) * p.y;
      }
      const double m = std::max<std::size_t>(core_texels.size(), 1);
      const double vx = sxx / m - (sx / m) * (sx / m), vy = syy / m - (sy / m) * (sy / m);
      radius_out = std::max(
          1.0f, static_cast<float>(settings.radius_sigmas * std::sqrt(std::max({vx, vy, 0.0}))));
      src.angular_radius = radius_out * texel_angle;
    }

    // The removed texels: the halo texels within the radius of the source.
    const float cos_r = std::cos(std::min(radius_out, static_cast<float>(kPi)));
    for (std::uint32_t i : mine) {
      bool inside;
      if (unit) {
        inside = glm::dot(direction(i), src.direction) >= cos_r;
      } else {
        const glm::vec3 d = point(i) - mean;
        inside = glm::dot(d, d) <= radius_out * radius_out;
      }
      if (inside) src.texels.push_back(i);
    }
    // The chosen cluster leaves D^l; its texels are removed too if the radius missed all.
    for (std::size_t j = 0; j < set.size(); ++j)
      if (static_cast<std::size_t>(km.assignment[j]) == chosen) {
        taken[set[j]] = 1;
        src.light_texels += 1;
        src.cluster_share += static_cast<float>(static_cast<double>(lum[set[j]]) * omega(set[j]) /
                                                out.total_energy);  // 003's luminanceLoss
      }
    if (settings.halo_set == HaloSet::kConnected)
      for (std::uint32_t i : mine) taken[i] = 1;  // its glow is not another source
    if (src.texels.empty()) {
      for (std::size_t j = 0; j < set.size(); ++j)
        if (static_cast<std::size_t>(km.assignment[j]) == chosen) src.texels.push_back(set[j]);
      std::sort(src.texels.begin(), src.texels.end());
    }
    const int index = static_cast<int>(out.sources.size());
    double energy = 0;
    glm::dvec3 irr(0.0);
    double solid = 0;
    for (std::uint32_t i : src.texels) {
      owner[i] = index;
      const double o = omega(i);
      energy += static_cast<double>(lum[i]) * o;  // the loss from the removed set itself
      irr += o * glm::dvec3(map.rgb[3 * i], map.rgb[3 * i + 1], map.rgb[3 * i + 2]);
      solid += o;
      remaining_blurred -= static_cast<double>(blurred[i]) * o;
    }
    src.energy_share = static_cast<float>(energy / out.total_energy);
    src.solid_angle = static_cast<float>(solid);
    src.irradiance = glm::vec3(irr);
    src.radiance = solid > 0 ? glm::vec3(irr / solid) : glm::vec3(0.0f);
    azimuth_elevation(src.direction, src.azimuth_deg, src.elevation_deg);
    out.sources.push_back(std::move(src));
    k = std::max(1, k - 1);  // nLightClusters - 1 per source found (Algorithm 1)
  }
  return finish();
}

}  // namespace penumbra::environment
