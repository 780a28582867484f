// Multi-scale horizon march ([Meier13] eq. 4.5-4.14, 4.22-4.25, sec. 5.2).
//
// Layout: a receiver texel p is an integer grid point, so sample i of azimuth k sits at
// p + d_i * dir_k, whose integer part and bilinear weights are the same for every texel. The
// march therefore runs one row segment of the region at a time, sample by sample: the texels
// of the segment read contiguous memory with shared weights, and the loops vectorise (the
// slopes, then detail::fast_atan_array). The texels whose sample i is inside the field form
// one contiguous range of the segment, nested in the range of sample i - 1 (rays are straight
// and the field convex), so dropping the outside samples is shrinking that range.
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

#include "fast_math.h"
#include "march_spline.h"
#include "sweep_geometry.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;

// c ? x : y through bit masks. GCC (with the default -ftrapping-math) will not if-convert a
// float select whose operands it would have to compute speculatively, which keeps such loops
// scalar; masks evaluate both sides and vectorise.
inline float pick(bool c, float x, float y) {
  const std::uint32_t m = 0u - static_cast<std::uint32_t>(c);
  return std::bit_cast<float>((std::bit_cast<std::uint32_t>(x) & m) |
                              (std::bit_cast<std::uint32_t>(y) & ~m));
}

// Where sample i of azimuth k falls relative to the receiver: integer offset, bilinear
// fractions, and whether the bilinear footprint reaches the next column / row.
struct SampleOffset {
  int dx, dy, sx, sy;
  float fx, fy;
};

// Everything that depends on the pyramid and the parameters but not on the texel.
struct Plan {
  int n = 0, n_phi = 0;
  std::vector<double> d;  // d_i in cells: d_0 = 1, d_{i+1} = d_i + sr^i ([Meier13] sec. 4.2.1)
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
      // and a larger lo is sharper ([Meier13] sec. 4.2.1). The thesis's index runs from coarse to
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
        detail::split_offset(d[i] * cx, o.dx, o.fx);
        detail::split_offset(d[i] * cy, o.dy, o.fy);
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
  validate_horizon_params(name + ": horizon march", params, pyr.width(), pyr.height(), region);
  if (!(march.level_offset >= 0) || !std::isfinite(march.level_offset))
    fail("level offset " + std::to_string(march.level_offset) + " must be finite and >= 0");
}

constexpr int kVector = 8;  // lanes per vector: the slope loop runs whole vectors

// Scratch for one row segment of `lanes` texels.
struct Row {
  std::size_t stride = 0;
  std::vector<float> angle;      // n rows of `stride` (lanes + a vector's slack): sample i's angles
  std::vector<int> lo, hi;       // per sample: lanes [lo, hi) have it inside the field
  std::vector<int> count;        // local light: samples the lane's spline uses
  const int* last = nullptr;     // local light, this row: last sample index the spline may use
  const float* reach = nullptr;  // local light, this row: the light as a spline parameter
  std::vector<float> best;
};

using detail::knot_value;  // [Meier13] eq. 4.8-4.12
using detail::mid_value;

// The hot loops, over restrict pointers so that they vectorise without alias checks.
// Elevation slopes of `vectors` whole vectors of lanes (eq. 4.5): bilinear height at the
// sample minus the receiver's, over the distance.
void slopes(const float* __restrict r0, const float* __restrict r1, const float* __restrict rec,
            float* __restrict dst, int vectors, int sx, float fx, float fy, float inv) {
  for (int v = 0; v < vectors; ++v, r0 += kVector, r1 += kVector, rec += kVector, dst += kVector)
    for (int j = 0; j < kVector; ++j) {
      const float top = r0[j] + fx * (r0[j + sx] - r0[j]);
      const float bottom = r1[j] + fx * (r1[j + sx] - r1[j]);
      dst[j] = (top + fy * (bottom - top) - rec[j]) * inv;
    }
}
void max_knots(float* __restrict best, const float* __restrict am, const float* __restrict a0,
               const float* __restrict a1, int lo, int hi) {
  for (int x = lo; x < hi; ++x) best[x] = std::max(best[x], knot_value(am[x], a0[x], a1[x]));
}
void max_mids(float* __restrict best, const float* __restrict am, const float* __restrict a0,
              const float* __restrict a1, const float* __restrict a2, int lo, int hi) {
  for (int x = lo; x < hi; ++x) best[x] = std::max(best[x], mid_value(am[x], a0[x], a1[x], a2[x]));
}

// Horizon of azimuth k for texels [x0, x0 + lanes) of row y, written to `out`; kLight: the
// local light's limits (row.last, row.reach) apply.
//
// Sample i is inside the field for lanes [lo_i, hi_i), nested in [lo_{i-1}, hi_{i-1}). Row i
// of the angle table holds sample i for those lanes, and for the lanes that just dropped out
// (inside at i - 1 only) a copy of sample i - 1: the spline's end replicates the last sample
// (rows past the last are clamped to it, as is row -1 to row 0). Other entries are stale and
// never read unmasked.
template <bool kLight>
void march_row_azimuth(const HeightPyramid& pyr, const Plan& plan, const HorizonParams& params,
                       int k, int y, int x0, int lanes, Row& row, HorizonGrid& out) {
  const int w = pyr.width(), h = pyr.height(), n = plan.n;
  // Receiver height: level 0 (the exact texel) rather than the sample's level h_i(x, y) of eq.
  // 4.5: a filtered receiver sinks on ridges and rises in valleys. Against brute force the two
  // are within 1e-3 rad of mean error for lo >= 2, level 0 is better for lo < 2 and cheaper.
  const float* receiver = pyr.level_data(0) + static_cast<std::size_t>(y) * w + x0;
  const float* end = pyr.level_data(n - 1) + static_cast<std::size_t>(w) * h;  // all levels
  float* table = row.angle.data();
  int samples = 0;  // samples inside the field for at least one lane
  for (int i = 0; i < n; ++i) {
    const SampleOffset& o = plan.at[static_cast<std::size_t>(k) * n + i];
    const int yy = y + o.dy;
    // Lanes whose bilinear footprint [x + dx, x + dx + sx] lies inside [0, w - 1].
    const int a = std::max({0, -o.dx - x0, i > 0 ? row.lo[i - 1] : 0});
    const int b = std::min({lanes, w - o.sx - o.dx - x0, i > 0 ? row.hi[i - 1] : lanes});
    if (yy < 0 || yy + o.sy > h - 1 || a >= b) break;
    row.lo[i] = a;
    row.hi[i] = b;
    samples = i + 1;
    float* cur = table + static_cast<std::size_t>(i) * row.stride;
    const float* prev = cur - row.stride;
    // Lane a's footprint, at or after the level's first sample.
    const float* r0 =
        pyr.level_data(plan.level[i]) + static_cast<std::size_t>(yy) * w + (x0 + a + o.dx);
    const float* r1 = r0 + static_cast<std::size_t>(o.sy) * w;
    const float* rec = receiver + a;
    float* dst = cur + a;
    const float fx = o.fx, fy = o.fy, inv = plan.inv_metres[i];
    const int sx = o.sx;
    // Whole vectors: the lanes past b compute garbage (overwritten below or never read), and
    // read at most kVector - 1 floats past the footprint, inside the pyramid's storage.
    const std::ptrdiff_t room = std::min(end - (r1 + sx), end - rec);
    const int run =
        static_cast<int>(std::min<std::ptrdiff_t>((b - a + kVector - 1) / kVector * kVector, room));
    // Eq. 4.5-4.6: elevation of the filtered terrain at distance d_i.
    slopes(r0, r1, rec, dst, run / kVector, sx, fx, fy, inv);
    for (int j = run / kVector * kVector; j < run; ++j) {  // only at the pyramid's very end
      const float top = r0[j] + fx * (r0[j + sx] - r0[j]);
      const float bottom = r1[j] + fx * (r1[j + sx] - r1[j]);
      dst[j] = (top + fy * (bottom - top) - rec[j]) * inv;
    }
    detail::fast_atan_array(dst, static_cast<std::size_t>(run));
    if (i > 0) {  // lanes that just dropped out repeat their last sample
      std::copy(prev + row.lo[i - 1], prev + a, cur + row.lo[i - 1]);
      std::copy(prev + b, prev + row.hi[i - 1], cur + b);
    }
    if constexpr (kLight) {
      // Eq. 4.24: the lane's samples past the first one beyond the light repeat that one.
      if (i > 0)
        for (int x = a; x < b; ++x) cur[x] = pick(i <= row.last[x], cur[x], prev[x]);
      for (int x = a; x < b; ++x) row.count[x] = std::min(i, row.last[x]) + 1;
    }
  }

  // Eq. 4.13: maximum of the spline over its knots and mid-points.
  const float none = -std::numeric_limits<float>::infinity();
  std::fill(row.best.begin(), row.best.end(), none);
  float* best = row.best.data();
  auto at = [&](int i) {
    return table + static_cast<std::size_t>(std::clamp(i, 0, samples - 1)) * row.stride;
  };
  for (int i = 0; i < samples; ++i) {
    const float *am = at(i - 1), *a0 = at(i), *a1 = at(i + 1), *a2 = at(i + 2);
    if constexpr (!kLight) {
      max_knots(best, am, a0, a1, row.lo[i], row.hi[i]);
      if (i + 1 < samples) max_mids(best, am, a0, a1, a2, row.lo[i + 1], row.hi[i + 1]);
    } else {
      // Eq. 4.25: only the part of the spline up to the light's distance, and only its samples.
      const float knot_at = static_cast<float>(i), mid_at = i + 0.5f;
      for (int x = row.lo[i]; x < row.hi[i]; ++x) {
        const bool use_knot = (i < row.count[x]) & (knot_at <= row.reach[x]);
        const bool use_mid = (i + 1 < row.count[x]) & (mid_at <= row.reach[x]);
        const float knot = knot_value(am[x], a0[x], a1[x]);
        const float mid = mid_value(am[x], a0[x], a1[x], a2[x]);
        best[x] = std::max(best[x], std::max(pick(use_knot, knot, none), pick(use_mid, mid, none)));
      }
    }
  }
  if constexpr (kLight) {
    // The spline at the light's own distance, when that lies inside its domain.
    for (int x = samples > 0 ? row.lo[0] : 0; x < (samples > 0 ? row.hi[0] : 0); ++x) {
      const float u = row.reach[x];
      if (!(u > 0 && u < static_cast<float>(row.count[x] - 1))) continue;
      const int j = static_cast<int>(u);
      const float t = u - static_cast<float>(j), t2 = t * t, t3 = t2 * t;
      const float wt[4] = {(1 - t) * (1 - t) * (1 - t) / 6, (3 * t3 - 6 * t2 + 4) / 6,
                           (-3 * t3 + 3 * t2 + 3 * t + 1) / 6, t3 / 6};  // eq. 4.9-4.12
      float v = 0;
      for (int q = 0; q < 4; ++q) v += wt[q] * at(j - 1 + q)[x];
      best[x] = std::max(best[x], v);
    }
  }

  for (int x = 0; x < lanes; ++x) {
    float v = best[x] == none ? -kHalfPi : best[x];  // no sample in range: straight down
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
  row.stride = static_cast<std::size_t>(lanes) + kVector;
  row.angle.resize(static_cast<std::size_t>(plan.n) * row.stride);
  row.lo.resize(plan.n);
  row.hi.resize(plan.n);
  row.count.resize(lanes);
  row.best.resize(lanes);
  // Local light: the limits of every texel of the region (they do not depend on the azimuth).
  std::vector<int> last;
  std::vector<float> reach;
  if (params.limit_to_point) {
    last.resize(region.count());
    reach.resize(region.count());
    const glm::vec2 light = *params.limit_to_point / pyramid.cell_size();
    for (int y = region.y0; y < region.y1; ++y)
      for (int x = region.x0; x < region.x1; ++x) {
        const double ex = light.x - static_cast<double>(x), ey = light.y - static_cast<double>(y);
        const std::size_t t = static_cast<std::size_t>(y - region.y0) * lanes + (x - region.x0);
        light_limits(plan, std::sqrt(ex * ex + ey * ey), last[t], reach[t]);
      }
  }
  // Azimuth outside, rows inside: row y + 1 reads the level rows that row y read, shifted by
  // one, while they are still in the cache.
  for (int k = 0; k < params.azimuths; ++k)
    for (int y = region.y0; y < region.y1; ++y) {
      if (params.limit_to_point) {
        const std::size_t t = static_cast<std::size_t>(y - region.y0) * lanes;
        row.last = last.data() + t;
        row.reach = reach.data() + t;
        march_row_azimuth<true>(pyramid, plan, params, k, y, region.x0, lanes, row, out);
      } else {
        march_row_azimuth<false>(pyramid, plan, params, k, y, region.x0, lanes, row, out);
      }
    }
}

}  // namespace penumbra::terrain_shadow
