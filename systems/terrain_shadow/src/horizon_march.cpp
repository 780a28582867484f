// Multi-scale horizon march (000_7ffde676d1c99e20.txt eq. 4.5-4.14, 4.22-4.25, sec. 5.2).
//
// Layout: a receiver texel p is an integer grid point, so sample i of azimuth k sits at
// p + d_i * dir_k, whose integer part and bilinear weights are the same for every texel. The
// march therefore runs one row segment of the region at a time, sample by sample, and the
// texels of the segment read contiguous memory with shared weights: the loop vectorises. The
// texels whose sample i is still inside the field form one contiguous range of the segment,
// nested in the range of sample i - 1 (rays are straight and the field convex), so outside
// samples are dropped by shrinking that range; a dropped sample repeats the lane's previous
// angle, which makes the B-spline's end replicate the last sample, and the lane's sample count
// masks the knots beyond it.
#include "penumbra/systems/terrain_shadow/horizon_march.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::terrain_shadow {
namespace {

constexpr float kHalfPi = std::numbers::pi_v<float> / 2;
constexpr float kQuarterPi = std::numbers::pi_v<float> / 4;

// c ? x : y through bit masks. GCC (with the default -ftrapping-math) will not if-convert a
// float select whose operands it would have to compute speculatively, which keeps the loops
// below scalar; masks evaluate both sides and vectorise.
inline float pick(bool c, float x, float y) {
  const std::uint32_t m = 0u - static_cast<std::uint32_t>(c);
  return std::bit_cast<float>((std::bit_cast<std::uint32_t>(x) & m) |
                              (std::bit_cast<std::uint32_t>(y) & ~m));
}

// atan without branches: Cephes atanf's reduction to |r| <= tan(pi/8) and its degree-9 odd
// polynomial. Max error 1.7e-7 rad (measured against double std::atan); atan(+-inf) = +-pi/2.
inline float fast_atan(float z) {
  const float a = std::fabs(z);
  const bool mid = a > 0.414213562f, big = a > 2.414213562f;
  const float num = pick(big, -1.0f, pick(mid, a - 1.0f, a));
  const float den = pick(big, a, pick(mid, a + 1.0f, 1.0f));
  const float base = pick(big, kHalfPi, pick(mid, kQuarterPi, 0.0f));
  const float r = num / den, r2 = r * r;
  const float p = (((8.05374449538e-2f * r2 - 1.38776856032e-1f) * r2 + 1.99777106478e-1f) * r2 -
                   3.33329491539e-1f) *
                      r2 * r +
                  r;
  return std::copysign(base + p, z);
}

// Where sample i of azimuth k falls relative to the receiver: integer offset, bilinear
// fractions, and whether the bilinear footprint reaches the next column / row.
struct SampleOffset {
  int dx, dy, sx, sy;
  float fx, fy;
};

// Split an offset into floor and fraction, snapping fractions within 1e-5 of a grid line (the
// axis and diagonal azimuths, whose cos / sin are off by ~1e-8) onto it.
void split(double v, int& whole, float& frac) {
  double f = std::floor(v), r = v - f;
  if (r > 1 - 1e-5) {
    f += 1;
    r = 0;
  } else if (r < 1e-5) {
    r = 0;
  }
  whole = static_cast<int>(f);
  frac = static_cast<float>(r);
}

// Everything that depends on the pyramid and the parameters but not on the texel.
struct Plan {
  int n = 0, n_phi = 0;
  std::vector<double> d;          // d_i in cells: d_0 = 1, d_{i+1} = d_i + sr^i (000 sec. 4.2.1)
  std::vector<float> inv_metres;  // 1 / (d_i * cell_size)
  std::vector<int> level;         // pyramid level read by sample i (eq. 4.14, see below)
  std::vector<SampleOffset> at;   // [k * n + i]

  Plan(const HeightPyramid& pyr, int azimuths, float level_offset)
      : n(pyr.levels()), n_phi(azimuths) {
    const double sr = std::exp2(1.0 / pyr.level_step());
    const double shift = pyr.level_step() * static_cast<double>(level_offset);
    double di = 1, spacing = 1;
    for (int i = 0; i < n; ++i) {
      d.push_back(di);
      inv_metres.push_back(static_cast<float>(1.0 / (di * pyr.cell_size())));
      // Eq. 4.14 offsets the level towards the finer end by ls * lo: sample i (spacing sr^i)
      // reads the level filtered for spacing sr^i / 2^lo, so lo = 0 is the alias-free choice
      // and a larger lo is sharper (000 sec. 4.2.1). The thesis's index runs from coarse to
      // fine, hence its "+"; with level 0 finest it is a "-".
      level.push_back(std::clamp(static_cast<int>(std::ceil(i - shift - 1e-9)), 0, n - 1));
      di += spacing;
      spacing *= sr;
    }
    at.resize(static_cast<std::size_t>(n_phi) * n);
    for (int k = 0; k < n_phi; ++k) {
      // Rounded to float first, as the other horizon methods do.
      const double phi = static_cast<float>(2.0 * std::numbers::pi * k / n_phi);
      const double cx = std::cos(phi), cy = std::sin(phi);
      for (int i = 0; i < n; ++i) {
        SampleOffset& o = at[static_cast<std::size_t>(k) * n + i];
        split(d[i] * cx, o.dx, o.fx);
        split(d[i] * cy, o.dy, o.fy);
        o.sx = o.fx > 0 ? 1 : 0;
        o.sy = o.fy > 0 ? 1 : 0;
      }
    }
  }
};

// Per-texel limits of a local light (eq. 4.24-4.25): the light's plane distance dl in cells.
// last_sample: the first sample beyond dl (the last one the spline may use); reach: dl as a
// spline parameter (knot i at d_i, linear in between), -1 when dl < d_0 (nothing in range).
void light_limits(const Plan& plan, double dl, int& last_sample, float& reach) {
  const auto beyond = std::upper_bound(plan.d.begin(), plan.d.end(), dl);
  const int k = static_cast<int>(beyond - plan.d.begin());
  last_sample = std::min(k, plan.n - 1);
  if (k == 0) {
    reach = -1;
  } else if (k == plan.n) {
    reach = static_cast<float>(plan.n - 1);
  } else {
    reach = static_cast<float>(k - 1 + (dl - plan.d[k - 1]) / (plan.d[k] - plan.d[k - 1]));
  }
}

void validate(const HeightPyramid& pyr, const HorizonParams& params, const MarchParams& march,
              const TexelRect& region) {
  const std::string name = pyr.source().empty() ? std::string("height field") : pyr.source();
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument(name + ": horizon march: " + why);
  };
  if (pyr.levels() == 0) fail("the pyramid has not been built");
  if (!std::isfinite(params.height_scale))
    fail("height scale " + std::to_string(params.height_scale) + " must be finite");
  if (params.azimuths < 3)
    fail("needs at least 3 azimuths, got " + std::to_string(params.azimuths));
  if (params.limit_to_point &&
      !(std::isfinite(params.limit_to_point->x) && std::isfinite(params.limit_to_point->y)))
    fail("light position must be finite");
  if (!(march.level_offset >= 0) || !std::isfinite(march.level_offset))
    fail("level offset " + std::to_string(march.level_offset) + " must be finite and >= 0");
  if (region.x0 < 0 || region.y0 < 0 || region.x1 > pyr.width() || region.y1 > pyr.height() ||
      region.x0 > region.x1 || region.y0 > region.y1)
    fail("region [" + std::to_string(region.x0) + ", " + std::to_string(region.x1) + ") x [" +
         std::to_string(region.y0) + ", " + std::to_string(region.y1) + ") is outside the field");
}

// Scratch for one row segment of `lanes` texels.
struct Row {
  std::vector<float> angle;  // n x lanes: angle of sample i, or the lane's previous one
  std::vector<int> count;    // samples inside the field (and the light's range) per lane
  std::vector<int> last;     // local light: last sample index the spline may use
  std::vector<float> reach;  // local light: spline parameter of the light, -1: none
  std::vector<float> best;
};

// Horizon of azimuth k for texels [x0, x0 + lanes) of row y, written to `out`; kLight: a
// local light's limits (row.last, row.reach) apply.
template <bool kLight>
void march_row_azimuth(const HeightPyramid& pyr, const Plan& plan, const HorizonParams& params,
                       int k, int y, int x0, int lanes, Row& row, HorizonGrid& out) {
  const int w = pyr.width(), h = pyr.height(), n = plan.n;
  // Receiver height: level 0 (the exact texel) rather than the sample's level h_i(x, y) of eq.
  // 4.5: a filtered receiver sinks on ridges and rises in valleys, which biases every angle
  // (the tests against brute force measure both; level 0 is the more accurate).
  const float* receiver = pyr.level_data(0) + static_cast<std::size_t>(y) * w + x0;
  std::fill(row.count.begin(), row.count.end(), 0);
  int samples = 0;  // samples with at least one lane inside
  for (int i = 0; i < n; ++i) {
    const SampleOffset& o = plan.at[static_cast<std::size_t>(k) * n + i];
    const int yy = y + o.dy;
    // Lanes whose footprint [x + dx, x + dx + sx] lies inside [0, w - 1]: [a, b).
    const int a = std::max(0, -o.dx - x0), b = std::min(lanes, w - 1 - o.sx - o.dx - x0 + 1);
    if (yy < 0 || yy + o.sy > h - 1 || a >= b) break;
    float* cur = row.angle.data() + static_cast<std::size_t>(i) * lanes;
    const float* prev = i > 0 ? cur - lanes : nullptr;
    if (i > 0) {
      std::copy(prev, prev + a, cur);
      std::copy(prev + b, prev + lanes, cur + b);
    }
    // Lane a's footprint, at or after the level's first sample.
    const float* r0 =
        pyr.level_data(plan.level[i]) + static_cast<std::size_t>(yy) * w + (x0 + a + o.dx);
    const float* r1 = r0 + static_cast<std::size_t>(o.sy) * w;
    const float* rec = receiver + a;
    float* dst = cur + a;
    const float fx = o.fx, fy = o.fy, inv = plan.inv_metres[i];
    const int sx = o.sx;
    // Eq. 4.5-4.6: elevation of the filtered terrain at distance d_i.
    for (int j = 0; j < b - a; ++j) {
      const float top = r0[j] + fx * (r0[j + sx] - r0[j]);
      const float bottom = r1[j] + fx * (r1[j + sx] - r1[j]);
      dst[j] = fast_atan((top + fy * (bottom - top) - rec[j]) * inv);
    }
    if (kLight && i > 0)  // eq. 4.24: samples past the first one beyond the light repeat it
      for (int x = a; x < b; ++x) cur[x] = pick(i <= row.last[x], cur[x], prev[x]);
    for (int x = a; x < b; ++x) row.count[x] = i + 1;
    samples = i + 1;
  }
  if (kLight)
    for (int x = 0; x < lanes; ++x) row.count[x] = std::min(row.count[x], row.last[x] + 1);

  // Eq. 4.8-4.13, sec. 5.2: maximum of the uniform cubic B-spline through the angles, at the
  // knots (1/6 2/3 1/6) and the mid-points (1/48 23/48 23/48 1/48). A lane's angles past its
  // count repeat its last one; knots past the count (or the light, eq. 4.25) are masked.
  const float none = -std::numeric_limits<float>::infinity();
  std::fill(row.best.begin(), row.best.end(), none);
  const float* base = row.angle.data();
  for (int i = 0; i < samples; ++i) {
    const float* am = base + static_cast<std::size_t>(std::max(i - 1, 0)) * lanes;
    const float* a0 = base + static_cast<std::size_t>(i) * lanes;
    const float* a1 = base + static_cast<std::size_t>(std::min(i + 1, samples - 1)) * lanes;
    const float* a2 = base + static_cast<std::size_t>(std::min(i + 2, samples - 1)) * lanes;
    const float knot_at = static_cast<float>(i), mid_at = i + 0.5f;
    for (int x = 0; x < lanes; ++x) {
      const float knot = (am[x] + 4 * a0[x] + a1[x]) * (1.0f / 6);
      const float mid = (am[x] + 23 * (a0[x] + a1[x]) + a2[x]) * (1.0f / 48);
      const bool use_knot = (i < row.count[x]) & (!kLight | (knot_at <= row.reach[x]));
      const bool use_mid = (i + 1 < row.count[x]) & (!kLight | (mid_at <= row.reach[x]));
      row.best[x] =
          std::max(row.best[x], std::max(pick(use_knot, knot, none), pick(use_mid, mid, none)));
    }
  }
  if (kLight)  // eq. 4.25: the spline at the light's own distance, when inside its domain
    for (int x = 0; x < lanes; ++x) {
      const float u = row.reach[x];
      if (!(u > 0 && u < static_cast<float>(row.count[x] - 1))) continue;
      const int j = static_cast<int>(u);
      float wt[4];
      const float t = u - static_cast<float>(j), t2 = t * t, t3 = t2 * t;
      wt[0] = (1 - t) * (1 - t) * (1 - t) / 6;
      wt[1] = (3 * t3 - 6 * t2 + 4) / 6;
      wt[2] = (-3 * t3 + 3 * t2 + 3 * t + 1) / 6;
      wt[3] = t3 / 6;
      float v = 0;
      for (int q = 0; q < 4; ++q)
        v += wt[q] *
             base[static_cast<std::size_t>(std::clamp(j - 1 + q, 0, samples - 1)) * lanes + x];
      row.best[x] = std::max(row.best[x], v);
    }

  for (int x = 0; x < lanes; ++x) {
    float v = row.best[x];
    if (v == none) v = -kHalfPi;  // no sample in range (the field's or the light's)
    if (params.clamp_at_zero) v = std::max(v, 0.0f);
    out.texel(x0 + x, y)[k] = v;
  }
}

}  // namespace

void march_horizons(const HeightPyramid& pyramid, const HorizonParams& params,
                    const MarchParams& march, const TexelRect& region, HorizonGrid& out) {
  validate(pyramid, params, march, region);
  const int w = pyramid.width(), h = pyramid.height();
  if (out.width != w || out.height != h || out.azimuths != params.azimuths ||
      out.angles.size() != static_cast<std::size_t>(w) * h * params.azimuths)
    out.resize(w, h, params.azimuths);
  if (region.empty()) return;

  const Plan plan(pyramid, params.azimuths, march.level_offset);
  const int lanes = region.width();
  Row row;
  row.angle.resize(static_cast<std::size_t>(plan.n) * lanes);
  row.count.resize(lanes);
  row.last.assign(lanes, plan.n - 1);
  row.reach.assign(lanes, static_cast<float>(plan.n - 1));
  row.best.resize(lanes);
  for (int y = region.y0; y < region.y1; ++y) {
    if (params.limit_to_point) {
      const glm::vec2 light = *params.limit_to_point / pyramid.cell_size();
      for (int x = 0; x < lanes; ++x) {
        const double ex = light.x - static_cast<double>(region.x0 + x), ey = light.y - y;
        light_limits(plan, std::sqrt(ex * ex + ey * ey), row.last[x], row.reach[x]);
      }
    }
    for (int k = 0; k < params.azimuths; ++k) {
      if (params.limit_to_point)
        march_row_azimuth<true>(pyramid, plan, params, k, y, region.x0, lanes, row, out);
      else
        march_row_azimuth<false>(pyramid, plan, params, k, y, region.x0, lanes, row, out);
    }
  }
}

}  // namespace penumbra::terrain_shadow
