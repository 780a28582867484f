// Line-sweep horizons (Timonen and Westerholm 2010) and the brute-force ray march.
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sweep_geometry.h"

namespace penumbra::terrain_shadow {
namespace {

constexpr float kHalfPi = std::numbers::pi_v<float> / 2;

// Rounded to float once, so that the sweep and ray_horizon build the same frame.
float azimuth(int k, int n) {
  return static_cast<float>(2.0 * std::numbers::pi * k / n);
}

float to_angle(float slope, bool any, bool clamp) {
  if (!any) return clamp ? 0.0f : -kHalfPi;
  const float a = std::atan(slope);
  return clamp ? std::max(a, 0.0f) : a;
}

struct HullPoint {
  int j;
  float h;
};

// One azimuth over the region: sweep every line that passes through it, scatter the line
// samples' horizons onto the texels between lines (weights by minor distance), write plane k.
void sweep_azimuth(const assets::HeightField& f, const HorizonParams& p, const TexelRect& r, int k,
                   std::vector<float>& acc, std::vector<float>& weight,
                   std::vector<HullPoint>& hull, HorizonGrid& out) {
  const detail::AzimuthFrame frame(f, azimuth(k, p.azimuths));
  // Region in (major, minor) coordinates, half-open.
  const int u0 = frame.x_major ? r.x0 : r.y0, u1 = frame.x_major ? r.x1 : r.y1;
  const int v0 = frame.x_major ? r.y0 : r.x0, v1 = frame.x_major ? r.y1 : r.x1;
  const int rw = u1 - u0;
  acc.assign(r.count(), 0.0f);
  weight.assign(r.count(), 0.0f);

  // Lines b = c + slope * u with integer c bracketing every texel of the region.
  const double lo = std::min(v0 - frame.slope * u0, v0 - frame.slope * (u1 - 1));
  const double hi = std::max((v1 - 1) - frame.slope * u0, (v1 - 1) - frame.slope * (u1 - 1));
  const int c_lo = static_cast<int>(std::floor(lo)) - 1, c_hi = static_cast<int>(std::ceil(hi)) + 1;
  // Far end first: the horizon looks along +step, so sweep from the far side of the field down
  // to the near edge of the region.
  const int u_far = frame.step > 0 ? frame.major_size - 1 : 0;
  const int u_near = frame.step > 0 ? u0 : u1 - 1;

  for (int c = c_lo; c <= c_hi; ++c) {
    hull.clear();
    for (int u = u_far;; u -= frame.step) {
      double b;
      float h;
      const bool inside = frame.height_at(f, p.height_scale, c, u, b, h);
      if (inside) {
        const int j = frame.step * u;
        // Pop hull points that are not the tangent from this sample (Timonen 2010, sec. 4).
        while (hull.size() >= 2 &&
               detail::slope_between(j, h, hull[hull.size() - 2].j, hull[hull.size() - 2].h,
                                     frame.metres_per_step) >=
                   detail::slope_between(j, h, hull.back().j, hull.back().h, frame.metres_per_step))
          hull.pop_back();
        if (u >= u0 && u < u1) {
          const float s = hull.empty() ? 0.0f
                                       : detail::slope_between(j, h, hull.back().j, hull.back().h,
                                                               frame.metres_per_step);
          const float angle = to_angle(s, !hull.empty(), p.clamp_at_zero);
          const int bi = static_cast<int>(b);
          const float t = static_cast<float>(b - bi);
          // The line lies t above texel bi and 1 - t below texel bi + 1.
          auto add = [&](int v, float w) {
            if (v < v0 || v >= v1 || w <= 0) return;
            const std::size_t i = static_cast<std::size_t>(v - v0) * rw + (u - u0);
            acc[i] += w * angle;
            weight[i] += w;
          };
          add(bi, 1.0f - t);
          add(bi + 1, t);
        }
        hull.push_back({j, h});
      }
      if (u == u_near) break;
    }
  }

  for (int v = v0; v < v1; ++v)
    for (int u = u0; u < u1; ++u) {
      const std::size_t i = static_cast<std::size_t>(v - v0) * rw + (u - u0);
      const float a = weight[i] > 0 ? acc[i] / weight[i] : 0.0f;
      const int x = frame.x_major ? u : v, y = frame.x_major ? v : u;
      out.texel(x, y)[k] = a;
    }
}

void prepare_output(const assets::HeightField& f, const HorizonParams& p, HorizonGrid& out) {
  if (out.width != f.width || out.height != f.height || out.azimuths != p.azimuths)
    out.resize(f.width, f.height, p.azimuths);
}

}  // namespace

void sweep_horizons(const assets::HeightField& field, const HorizonParams& params,
                    const TexelRect& region, HorizonGrid& out) {
  validate_horizon_input(field, params, region);
  if (params.limit_to_point)
    throw std::invalid_argument(
        field.source + ": the line sweep has no distance limit (use march or brute force)");
  prepare_output(field, params, out);
  if (region.empty()) return;
  // Parallel over azimuths in blocks, so that threads write disjoint parts of each texel's
  // record (n_phi / 2 consecutive floats per thread with two threads).
  tbb::parallel_for(tbb::blocked_range<int>(0, params.azimuths, 4),
                    [&](const tbb::blocked_range<int>& ks) {
                      std::vector<float> acc, weight;
                      std::vector<HullPoint> hull;
                      for (int k = ks.begin(); k != ks.end(); ++k)
                        sweep_azimuth(field, params, region, k, acc, weight, hull, out);
                    });
}

namespace {

// Largest elevation slope seen from (u_start, offset + slope * u_start) at `start_height` along
// the frame's direction, over grid-line samples within max_distance; false if there are none.
bool line_slope(const assets::HeightField& field, float scale, const detail::AzimuthFrame& frame,
                double offset, double u_start, float start_height, float max_distance,
                float& best) {
  int u = frame.step > 0 ? static_cast<int>(std::floor(u_start)) + 1
                         : static_cast<int>(std::ceil(u_start)) - 1;
  bool any = false;
  for (; u >= 0 && u < frame.major_size; u += frame.step) {
    const float steps = static_cast<float>((u - u_start) * frame.step);
    if (steps * frame.metres_per_step > max_distance) break;
    double b;
    float h;
    if (!frame.height_at(field, scale, offset, u, b, h)) continue;
    const float s = (h - start_height) / (steps * frame.metres_per_step);
    if (!any || s > best) best = s;
    any = true;
  }
  return any;
}

}  // namespace

float ray_horizon(const assets::HeightField& field, float height_scale, glm::vec2 start,
                  float start_height, float phi, float max_distance, bool clamp_at_zero) {
  const detail::AzimuthFrame frame(field, phi);
  const double us = frame.x_major ? start.x : start.y, bs = frame.x_major ? start.y : start.x;
  float best = 0;
  const bool any = line_slope(field, height_scale, frame, bs - frame.slope * us, us, start_height,
                              max_distance, best);
  return to_angle(best, any, clamp_at_zero);
}

float sweep_line_horizon(const assets::HeightField& field, const HorizonParams& params, int x,
                         int y, int k) {
  float limit = std::numeric_limits<float>::infinity();
  if (params.limit_to_point) {
    const glm::vec2 d = *params.limit_to_point - glm::vec2(x, y) * field.cell_size;
    limit = std::sqrt(d.x * d.x + d.y * d.y);
  }
  // The sweep's two lines either side of the texel, in the sweep's order and weights.
  const detail::AzimuthFrame frame(field, azimuth(k, params.azimuths));
  const int u = frame.x_major ? x : y, v = frame.x_major ? y : x;
  const int c_upper = static_cast<int>(std::ceil(v - frame.slope * u));
  float acc = 0, weight = 0;
  for (int c = c_upper - 1; c <= c_upper; ++c) {
    double b;
    float h;
    if (!frame.height_at(field, params.height_scale, c, u, b, h)) continue;
    const int bi = static_cast<int>(b);
    const float t = static_cast<float>(b - bi);
    const float w = bi == v ? 1.0f - t : (bi + 1 == v ? t : 0.0f);
    if (w <= 0) continue;
    float s = 0;
    const bool any = line_slope(field, params.height_scale, frame, c, u, h, limit, s);
    acc += w * to_angle(s, any, params.clamp_at_zero);
    weight += w;
  }
  return weight > 0 ? acc / weight : 0.0f;
}

void brute_force_horizons(const assets::HeightField& field, const HorizonParams& params,
                          const TexelRect& region, HorizonGrid& out, BruteForceSampling sampling) {
  validate_horizon_input(field, params, region);
  prepare_output(field, params, out);
  tbb::parallel_for(region.y0, region.y1, [&](int y) {
    for (int x = region.x0; x < region.x1; ++x) {
      float limit = std::numeric_limits<float>::infinity();
      if (params.limit_to_point) {
        const glm::vec2 d = *params.limit_to_point - glm::vec2(x, y) * field.cell_size;
        limit = std::sqrt(d.x * d.x + d.y * d.y);
      }
      for (int k = 0; k < params.azimuths; ++k) {
        const float phi = azimuth(k, params.azimuths);
        if (sampling == BruteForceSampling::kTexelRays) {
          out.texel(x, y)[k] =
              ray_horizon(field, params.height_scale, glm::vec2(x, y),
                          params.height_scale * field.at(x, y), phi, limit, params.clamp_at_zero);
          continue;
        }
        out.texel(x, y)[k] = sweep_line_horizon(field, params, x, y, k);
      }
    }
  });
}

}  // namespace penumbra::terrain_shadow
