// The line sweep, sixteen lines per step on AVX2 lanes (sweep_lanes.h). [Timonen10] sec. 4.
// Compiled twice: here for the x86-64-v3 baseline, and by sweep_lanes_avx512.cpp for AVX-512
// (PENUMBRA_SWEEP_LANES_AVX512: the kernels go into namespace avx512 instead of avx2, the
// shared parts and the run-time choice between them are compiled here only).
#include "sweep_lanes.h"

#ifdef __AVX2__

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#ifndef PENUMBRA_SWEEP_LANES_AVX512  // LaneFields: compiled for the baseline only
#include <tbb/parallel_for.h>
#endif

#include "fast_math.h"
#include "lanes.h"
#include "sweep_geometry.h"
#ifdef PENUMBRA_SWEEP_LANES_AVX512
#include "fast_math16.h"  // kAll, fast_atan16, transpose16
#endif

namespace penumbra::terrain_shadow::detail {
namespace {

constexpr int kPad = kGroupLines;  // zero samples either side of a padded column
// Accumulator slots either side of the minor range (at least kGroupLines + 8; 32, so that a row
// of 16n texels starts on a cache line, as acc does).
constexpr int kAccPad = 2 * kGroupLines;
constexpr int kVectors = kGroupLines / 8;  // AVX2 vectors per group
constexpr int kGroupShift = 4;             // kGroupLines == 1 << kGroupShift
static_assert(kGroupLines == 1 << kGroupShift);

}  // namespace

#ifdef PENUMBRA_SWEEP_LANES_AVX512
#define PENUMBRA_SWEEP_KERNELS avx512
#else
#define PENUMBRA_SWEEP_KERNELS avx2
namespace {

// Whether row y of the y-major copy holds row y of `f`, bit for bit (not values: -0 and NaNs).
bool row_held(const LaneFields& fields, const data::HeightField& f, int y) {
  return std::memcmp(f.heights.data() + static_cast<std::size_t>(y) * f.width,
                     fields.y_major.data() + static_cast<std::size_t>(y) * fields.stride_y + kPad,
                     static_cast<std::size_t>(f.width) * sizeof(float)) == 0;
}

}  // namespace

void LaneFields::assign(const data::HeightField& f) {
  stride_x = f.height + 2 * kPad + 1;
  stride_y = f.width + 2 * kPad + 1;
  // The padding is zeros and only samples are written below, so storage of the same shape is
  // not cleared again (a full sweep assigns at every call).
  const std::size_t nx = static_cast<std::size_t>(f.width) * stride_x;
  const std::size_t ny = static_cast<std::size_t>(f.height) * stride_y;
  const bool kept = x_major.size() == nx && y_major.size() == ny;
  if (!kept) {
    x_major.assign(nx, 0.0f);
    y_major.assign(ny, 0.0f);
  }
  // Bands of 8 rows: the rows, then their transposed copy in 8 x 8 blocks transposed in
  // registers; on one thread below 512^2 texels (there the copy costs less than two threads'
  // fork and join), in parallel bands of 64 rows from there. A band whose rows the copies hold
  // already is only read: rewriting lines that the other threads' caches hold from the last
  // sweep costs more than comparing them (docs/terrain_shadow_log.md, "Eleventh round" and "Twelfth
  // round").
  auto band = [&](int y0, int y1) {
    if (kept) {
      int y = y0;
      while (y < y1 && row_held(*this, f, y)) ++y;
      if (y == y1) return;
    }
    for (int y = y0; y < y1; ++y)
      std::copy_n(f.heights.data() + static_cast<std::size_t>(y) * f.width, f.width,
                  y_major.data() + static_cast<std::size_t>(y) * stride_y + kPad);
    const int w8 = y1 - y0 == 8 ? f.width / 8 * 8 : 0;
    for (int x = 0; x < w8; x += 8) {
      __m256 m[8];
      for (int i = 0; i < 8; ++i)
        m[i] = _mm256_loadu_ps(f.heights.data() + static_cast<std::size_t>(y0 + i) * f.width + x);
      transpose8(m);
      for (int i = 0; i < 8; ++i)
        _mm256_storeu_ps(x_major.data() + static_cast<std::size_t>(x + i) * stride_x + kPad + y0,
                         m[i]);
    }
    for (int x = w8; x < f.width; ++x)
      for (int y = y0; y < y1; ++y)
        x_major[static_cast<std::size_t>(x) * stride_x + kPad + y] = f.at(x, y);
  };
  auto rows = [&](int r0, int r1) {
    for (int y0 = r0; y0 < r1; y0 += 8) band(y0, std::min(y0 + 8, r1));
  };
  if (static_cast<std::size_t>(f.width) * f.height < 512 * 512) {
    rows(0, f.height);
    return;
  }
  tbb::parallel_for(0, (f.height + 63) / 64,
                    [&](int b) { rows(b * 64, std::min(b * 64 + 64, f.height)); });
}

TexelRect LaneFields::update(const data::HeightField& f) {
  const std::size_t w = static_cast<std::size_t>(f.width);
  if (stride_x != f.height + 2 * kPad + 1 || stride_y != f.width + 2 * kPad + 1 ||
      x_major.size() != w * stride_x ||
      y_major.size() != static_cast<std::size_t>(f.height) * stride_y) {
    assign(f);
    return TexelRect::all(f);
  }
  TexelRect d{f.width, f.height, 0, 0};
  for (int y = 0; y < f.height; ++y) {
    const float* src = f.heights.data() + y * w;
    float* row = y_major.data() + static_cast<std::size_t>(y) * stride_y + kPad;
    if (row_held(*this, f, y)) continue;
    for (int x = 0; x < f.width; ++x)
      if (std::bit_cast<std::uint32_t>(src[x]) != std::bit_cast<std::uint32_t>(row[x])) {
        row[x] = src[x];
        x_major[static_cast<std::size_t>(x) * stride_x + kPad + y] = src[x];
        d = {std::min(d.x0, x), std::min(d.y0, y), std::max(d.x1, x + 1), std::max(d.y1, y + 1)};
      }
  }
  return d.x0 < d.x1 ? d : TexelRect{};
}

void texel_records(const float* const* planes, const TexelRect& r, int k0, int k1,
                   HorizonGrid& out) {
  std::size_t i = 0;
  const bool blocks = (k1 - k0) % 8 == 0;
  // 16 azimuths starting on a cache line: each texel's run is a whole line, written with
  // streaming stores (no read for ownership; records this large do not stay in cache anyway).
  const bool lines = k1 - k0 == 16 && k0 % 16 == 0 && out.azimuths % 16 == 0 &&
                     reinterpret_cast<std::uintptr_t>(out.angles.data()) % 64 == 0;
  for (int y = r.y0; y < r.y1; ++y) {
    int x = r.x0;
    if (lines)
      for (; x + 8 <= r.x1; x += 8, i += 8) {
        __m256 m[8], n[8];
        for (int k = 0; k < 8; ++k) {
          m[k] = _mm256_loadu_ps(planes[k] + i);
          n[k] = _mm256_loadu_ps(planes[8 + k] + i);
        }
        transpose8(m);
        transpose8(n);
        for (int l = 0; l < 8; ++l) {
          float* dst = out.texel(x + l, y) + k0;
          _mm256_stream_ps(dst, m[l]);
          _mm256_stream_ps(dst + 8, n[l]);
        }
      }
    if (blocks)
      for (; x + 8 <= r.x1; x += 8, i += 8)
        for (int kb = 0; kb < k1 - k0; kb += 8) {
          __m256 m[8];
          for (int k = 0; k < 8; ++k) m[k] = _mm256_loadu_ps(planes[kb + k] + i);
          transpose8(m);
          for (int l = 0; l < 8; ++l) _mm256_storeu_ps(out.texel(x + l, y) + k0 + kb, m[l]);
        }
    for (; x < r.x1; ++x, ++i)
      for (int k = k0; k < k1; ++k) out.texel(x, y)[k] = planes[k - k0][i];
  }
  if (lines) _mm_sfence();  // the streaming stores visible before the task ends
}
#endif

namespace PENUMBRA_SWEEP_KERNELS {
namespace {

// The weight add() gives texel v (minor) of a column whose lines lie t above their texels: t
// from the line below unless v is the field's first row, then 1 - t from the line above unless
// v is its last (bmax) and t > 0, added in add()'s order. Every group crossing a column has the
// same t up to the rounding of c + slope u, so the weights need no array of their own.
float texel_weight(int v, int bmax, float t) {
  return (0.0f + (v >= 1 ? t : 0.0f)) + (v < bmax || t == 0.0f ? 1.0f - t : 0.0f);
}

// Whether texel_weight inside the field, t + (1 - t), rounds to 1 (then a / weight = a: the
// planes pass copies instead of dividing). It does for every t tried (10^6 random t).
bool interior_weight_is_one(float t) {
  return (0.0f + t) + (1.0f - t) == 1.0f;
}

// Where a group's receivers go: acc, layout [u - u0][v - v0 + kAccPad], `row` floats per u,
// and each column's t (t_of_u[u - u0]), for receivers with major coordinate in [rec_lo, rec_hi)
// and minor in [v0, v1).
struct Accumulator {
  float* acc;
  float* t_of_u;
  int u0, v0, v1, row, rec_lo, rec_hi;

  // Lane l's line lies t above texel b0 + l and 1 - t below texel b0 + l + 1: texel b0 + m gets
  // t times lane m - 1's angle, then 1 - t times lane m's, in the scalar sweep's order; one
  // store per slot (overlapping stores would stall on store forwarding).
  void add(int u, int b0, float t, const __m256 (&angle)[kVectors],
           const __m256 (&valid)[kVectors]) const {
    const __m256i rotate = _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6);  // lane l -> l + 1
    const __m256 lo = _mm256_set1_ps(1.0f - t), hi = _mm256_set1_ps(t), zero = _mm256_setzero_ps();
    const std::size_t q = static_cast<std::size_t>(u - u0) * row + (b0 - v0 + kAccPad);
    float* a = acc + q;
    t_of_u[u - u0] = t;
    __m256 prev_angle = zero, prev_valid = zero;  // the last vector, rotated
    for (int g = 0; g <= kVectors; ++g) {
      __m256 below_angle = zero, below_valid = zero, cur_angle = zero, cur_valid = zero;
      if (g < kVectors) {
        cur_angle = angle[g], cur_valid = valid[g];
        below_angle = _mm256_permutevar8x32_ps(cur_angle, rotate);
        below_valid = _mm256_permutevar8x32_ps(cur_valid, rotate);
      }
      // Lane 0 takes the previous vector's lane 7.
      const __m256 a_below = _mm256_blend_ps(below_angle, prev_angle, 1);
      const __m256 v_below = _mm256_blend_ps(below_valid, prev_valid, 1);
      prev_angle = below_angle, prev_valid = below_valid;
      const __m256 w_hi = _mm256_and_ps(v_below, hi), w_lo = _mm256_and_ps(cur_valid, lo);
      const __m256 s = _mm256_fmadd_ps(w_hi, a_below, _mm256_loadu_ps(a + 8 * g));
      _mm256_storeu_ps(a + 8 * g, _mm256_fmadd_ps(w_lo, cur_angle, s));
    }
  }
};

// The hull links' layout: the AVX-512 copy keeps each link's height and j side by side (one
// 64-bit gather element fetches both), the AVX2 copy in two arrays; link (slot, lane) is at
// (slot * kGroupLines + lane) * kLinkStride from link_h and from link_j.
#ifdef PENUMBRA_SWEEP_LANES_AVX512
constexpr std::size_t kLinkStride = 2;
#else
constexpr std::size_t kLinkStride = 1;
#endif

// A group's hull registers (run_group): per vector the lanes' sizes and top three points
// (a = the top, b, c: height and j).
struct HullRegisters {
  __m256i top[kVectors];
  __m256 ah[kVectors], aj[kVectors], bh[kVectors], bj[kVectors], ch[kVectors], cj[kVectors];
};

// The same per lane in memory: between the registers, a kept hull and the 512-bit walk.
struct HullLanes {
  alignas(64) std::int32_t size[kGroupLines];
  alignas(64) float p[6][kGroupLines];  // a, b, c: height, j

  void store(const HullRegisters& r) {
    const __m256* const regs[6] = {r.ah, r.aj, r.bh, r.bj, r.ch, r.cj};
    for (int g = 0; g < kVectors; ++g) {
      _mm256_store_si256(reinterpret_cast<__m256i*>(size + 8 * g), r.top[g]);
      for (int q = 0; q < 6; ++q) _mm256_store_ps(p[q] + 8 * g, regs[q][g]);
    }
  }
  void load_into(HullRegisters& r) const {
    __m256* const regs[6] = {r.ah, r.aj, r.bh, r.bj, r.ch, r.cj};
    for (int g = 0; g < kVectors; ++g) {
      r.top[g] = _mm256_load_si256(reinterpret_cast<const __m256i*>(size + 8 * g));
      for (int q = 0; q < 6; ++q) regs[q][g] = _mm256_load_ps(p[q] + 8 * g);
    }
  }
};

// The hull of `keep` into the links (the slots of its points, and slot 0's absent point) and
// registers, as a walk from the far end would have left them.
void restore_hull(const GroupHull& keep, float j_start, float* link_h, float* link_j,
                  HullRegisters& regs) {
  constexpr int W = kGroupLines;
  const float absent = j_start + 1.0f;
  HullLanes lanes;
  std::size_t o = 0;
  for (int l = 0; l < W; ++l) {
    const int m = keep.size[l];
    const float* ph = keep.h.data() + o;
    const float* pj = keep.j.data() + o;
    for (int i = 0; i < m; ++i) {  // each point's slot holds the point below it
      const std::size_t slot = (static_cast<std::size_t>(j_start - pj[i]) * W + l) * kLinkStride;
      link_h[slot] = i > 0 ? ph[i - 1] : 0.0f;
      link_j[slot] = i > 0 ? pj[i - 1] : absent;
    }
    lanes.size[l] = m;
    for (int d = 0; d < 3; ++d) {
      lanes.p[2 * d][l] = m > d ? ph[m - 1 - d] : 0.0f;
      lanes.p[2 * d + 1][l] = m > d ? pj[m - 1 - d] : absent;
    }
    o += static_cast<std::size_t>(m);
  }
  lanes.load_into(regs);
}

// The group's hull before column u into `keep`: the top three points from the registers, the
// rest down the links.
void take_hull(int cg, int u_start, int u, float j_start, const float* link_h, const float* link_j,
               const HullRegisters& regs, GroupHull& keep) {
  constexpr int W = kGroupLines;
  HullLanes lanes;
  lanes.store(regs);
  keep.h.clear();
  keep.j.clear();
  for (int l = 0; l < W; ++l) {
    const int m = lanes.size[l];
    keep.size[l] = m;
    const std::size_t o = keep.h.size();
    keep.h.resize(o + static_cast<std::size_t>(m));
    keep.j.resize(o + static_cast<std::size_t>(m));
    float* ph = keep.h.data() + o;
    float* pj = keep.j.data() + o;
    for (int i = m - 1, d = 0; i >= 0; --i, ++d) {
      if (d < 3) {
        ph[i] = lanes.p[2 * d][l], pj[i] = lanes.p[2 * d + 1][l];
      } else {  // the point below point i + 1
        const std::size_t slot =
            (static_cast<std::size_t>(j_start - pj[i + 1]) * W + l) * kLinkStride;
        ph[i] = link_h[slot], pj[i] = link_j[slot];
      }
    }
  }
  keep.cg = cg, keep.u_start = u_start, keep.u = u, keep.valid = true;
}

// What every group of an azimuth shares.
struct Sweep {
  AzimuthFrame frame;
  const float* heights;  // padded copy whose minor axis is contiguous
  int stride, bmax;
  bool clamp;
  float scale;

  Sweep(const data::HeightField& f, const LaneFields& fields, const HorizonParams& p, double phi)
      : frame(f, phi),
        heights(frame.x_major ? fields.x_major.data() : fields.y_major.data()),
        stride(frame.x_major ? fields.stride_x : fields.stride_y),
        bmax(frame.minor_size - 1),
        clamp(p.clamp_at_zero),
        scale(p.height_scale) {}

  // First line of the group holding line c: groups start at multiples of kGroupLines, so a
  // line's lane (and its arithmetic) never depends on which lines or region were asked for.
  static int group_of(int c) {
    return c >= 0 ? c / kGroupLines * kGroupLines
                  : -((-c + kGroupLines - 1) / kGroupLines * kGroupLines);
  }
  int far_end() const { return frame.step > 0 ? frame.major_size - 1 : 0; }

  // Sweeps lines cg..cg+kGroupLines-1 from the far end of the field down to u_stop, adding the
  // receivers' angles into `out`. With `keep`: starts from its hull instead where that was
  // taken for this group at or ahead of the first recorded column, and leaves there the hull
  // at that column.
  void run_group(int cg, int u_stop, const Accumulator& out, LaneScratch& sc,
                 GroupHull* keep = nullptr) const;
#ifdef PENUMBRA_SWEEP_LANES_AVX512
  // run_group's samples pass on AVX-512 (steps [s_begin, steps) of group cg from column
  // u_start): each step's first minor index and offset for eight steps at a time in doubles,
  // its mask from two shifts, then per step only the heights; the same values as the scalar
  // pass.
  void samples16(int cg, int s_begin, int steps, int u_start, LaneScratch& sc) const;
  // run_group's walk over the group's samples (steps [s_begin, steps)) with the sixteen lanes
  // in one 512-bit vector: one chain of pop rounds instead of two, lanes chosen by mask
  // registers; the same floats as the two 8-lane vectors. The registers come in and go back
  // out as those vectors; before step s_take (column u), take(u) runs with them written back.
  template <class Take>
  void walk16(const LaneScratch& sc, int s_begin, int steps, int s_take, int u_start, float j_start,
              const Accumulator& out, float* links, HullRegisters& regs, Take take) const;
#endif
};

void Sweep::run_group(int cg, int u_stop, const Accumulator& out, LaneScratch& sc,
                      GroupHull* keep) const {
  constexpr int W = kGroupLines, G = kVectors;
  // Columns where any of the group's lines is inside the field (widened by one).
  int ua = 0, ub = frame.major_size - 1;
  if (frame.slope != 0) {
    const double e[4] = {-cg / frame.slope, (bmax - cg) / frame.slope, -(cg + W - 1) / frame.slope,
                         (bmax - cg - W + 1) / frame.slope};
    ua = std::max(ua, static_cast<int>(std::floor(*std::min_element(e, e + 4))) - 1);
    ub = std::min(ub, static_cast<int>(std::ceil(*std::max_element(e, e + 4))) + 1);
  } else if (cg + W - 1 < 0 || cg > bmax) {
    return;
  }
  if (frame.step > 0)
    ub = std::min(ub, far_end()), ua = std::max(ua, u_stop);
  else
    ua = std::max(ua, far_end()), ub = std::min(ub, u_stop);
  if (ua > ub) return;

  const std::size_t cap = static_cast<std::size_t>(frame.major_size);
  if (sc.hull_h.size() < cap * W * kLinkStride) {
    sc.hull_h.resize(cap * W * kLinkStride), sc.hull_j.resize(cap * W);
  }
  // The hull as linked lists through the group's steps: step s's slot s * W + lane holds the
  // point that was on top of that lane's hull when the step pushed its sample (the sample's
  // own height and j are in registers, a = top). A pop then reads the new third point from
  // the slot of the old one, and a push is one contiguous store per vector.
  float* link_h = sc.hull_h.data();
  float* link_j = kLinkStride == 2 ? sc.hull_h.data() + 1 : sc.hull_j.data();
  const int u_start = frame.step > 0 ? ub : ua, u_end = frame.step > 0 ? ua : ub;
  const float j_start = static_cast<float>(frame.step * u_start);  // j = j_start - step index

  // Per vector: hull size per lane, and the top three hull points in registers (a = top - 1,
  // b = top - 2, c = top - 3): a pop needs only a and b, and the gather that refills c after a
  // pop is not on the path to the next comparison. Absent points sit at j_start + 1 (slot -1,
  // read as slot 0 and never used: `top` guards every use).
  HullRegisters regs;
  auto& top = regs.top;
  auto &ah = regs.ah, &aj = regs.aj, &bh = regs.bh, &bj = regs.bj, &ch = regs.ch, &cj = regs.cj;
  for (int g = 0; g < G; ++g) {
    top[g] = _mm256_setzero_si256();
    ah[g] = bh[g] = ch[g] = _mm256_setzero_ps();
    aj[g] = bj[g] = cj[g] = _mm256_set1_ps(j_start + 1.0f);
  }
  // Slot 0 holds the absent point (a step 0 without lanes in the field stores nothing), so that
  // a refill from an absent point reads an absent point, never an earlier group's link.
  for (int l = 0; l < W; ++l)
    link_h[l * kLinkStride] = 0.0f, link_j[l * kLinkStride] = j_start + 1.0f;
  const int steps = (u_start - u_end) * frame.step + 1;
  // The first recorded column's step (steps if none): where `keep` takes the hull.
  const int u_first =
      frame.step > 0 ? std::min(out.rec_hi - 1, u_start) : std::max(out.rec_lo, u_start);
  const int s_keep = std::clamp((u_start - u_first) * frame.step, 0, steps);
  int s_begin = 0;
  if (keep && keep->valid && keep->cg == cg && keep->u_start == u_start) {
    const int s_kept = (u_start - keep->u) * frame.step;
    if (s_kept > 0 && s_kept <= s_keep) {
      s_begin = s_kept;
      restore_hull(*keep, j_start, link_h, link_j, regs);
    }
  }
  // Where the hull is taken (-1: nowhere; not again where it was restored from).
  const int s_take = keep && !(s_begin > 0 && s_begin == s_keep) ? s_keep : -1;
  // The samples first, every step of the group (nothing carries from one step to the next, so
  // these loads and compares pipeline), then the hull walk over them: its pops are a latency
  // chain, and a short loop body refills faster after the pop loop's exits mispredict.
  if (sc.step_h.size() < static_cast<std::size_t>(steps) * W) {
    const std::size_t padded = static_cast<std::size_t>(steps) + 8;  // samples16's last eight
    sc.step_h.resize(static_cast<std::size_t>(steps) * W);
    sc.step_ok.resize(padded * W);
    sc.step_b0.resize(padded);
    sc.step_t.resize(padded);
  }
#ifdef PENUMBRA_SWEEP_LANES_AVX512
  samples16(cg, s_begin, steps, u_start, sc);
  walk16(sc, s_begin, steps, s_take, u_start, j_start, out, link_h, regs,
         [&](int u) { take_hull(cg, u_start, u, j_start, link_h, link_j, regs, *keep); });
#else
  const __m256 vscale = _mm256_set1_ps(scale);
  __m256i lane[G];
  for (int g = 0; g < G; ++g)
    lane[g] = _mm256_add_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(8 * g));
  for (int s = s_begin; s < steps; ++s) {
    const int u = u_start - s * frame.step;
    const double base = cg + frame.slope * u;  // lane l sits at base + l
    const int b0 = static_cast<int>(std::floor(base));
    sc.step_b0[s] = b0;
    if (b0 + W - 1 < 0 || b0 > bmax) continue;  // no lane inside the field
    const float t = static_cast<float>(base - b0);
    sc.step_t[s] = t;
    const float* col = heights + static_cast<std::ptrdiff_t>(u) * stride + kPad + b0;
    const __m256 vt = _mm256_set1_ps(t);
    for (int g = 0; g < G; ++g) {
      const __m256i b = _mm256_add_epi32(_mm256_set1_epi32(b0), lane[g]);
      // Inside the field: 0 <= b + t <= bmax (as AzimuthFrame::height_at).
      __m256i ok = _mm256_andnot_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), b),
                                       _mm256_cmpgt_epi32(_mm256_set1_epi32(bmax), b));
      if (t == 0.0f) ok = _mm256_or_si256(ok, _mm256_cmpeq_epi32(b, _mm256_set1_epi32(bmax)));
      const __m256 h0 = _mm256_loadu_ps(col + 8 * g), h1 = _mm256_loadu_ps(col + 8 * g + 1);
      const std::size_t at = static_cast<std::size_t>(s) * W + 8 * g;
      _mm256_storeu_ps(sc.step_h.data() + at,
                       _mm256_mul_ps(vscale, _mm256_fmadd_ps(vt, _mm256_sub_ps(h1, h0), h0)));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(sc.step_ok.data() + at), ok);
    }
  }
  const __m256 mps = _mm256_set1_ps(frame.metres_per_step), vj_start = _mm256_set1_ps(j_start);
  const __m256 minus_inf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  for (int s = s_begin, u = u_start - s_begin * frame.step; s < steps; ++s, u -= frame.step) {
    if (s == s_take) take_hull(cg, u_start, u, j_start, link_h, link_j, regs, *keep);
    const int b0 = sc.step_b0[s];
    if (b0 + W - 1 >= 0 && b0 <= bmax) {
      const float t = sc.step_t[s];
      const __m256 j = _mm256_set1_ps(static_cast<float>(frame.step * u));
      __m256i ok[G];
      __m256 valid[G], h[G];
      for (int g = 0; g < G; ++g) {
        const std::size_t at = static_cast<std::size_t>(s) * W + 8 * g;
        ok[g] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sc.step_ok.data() + at));
        valid[g] = _mm256_castsi256_ps(ok[g]);
        h[g] = _mm256_loadu_ps(sc.step_h.data() + at);
      }
      // Pop while the second point is at least as steep as the top (compared without
      // dividing; Timonen 2010, sec. 4), on every lane that still needs it; the G vectors'
      // chains are independent, so their latencies overlap.
      for (;;) {
        __m256 pop[G];
        __m256 any = _mm256_setzero_ps();
        for (int g = 0; g < G; ++g) {
          const __m256 can = _mm256_and_ps(
              valid[g], _mm256_castsi256_ps(_mm256_cmpgt_epi32(top[g], _mm256_set1_epi32(1))));
          const __m256 lhs = _mm256_mul_ps(_mm256_sub_ps(bh[g], h[g]), _mm256_sub_ps(aj[g], j));
          const __m256 rhs = _mm256_mul_ps(_mm256_sub_ps(ah[g], h[g]), _mm256_sub_ps(bj[g], j));
          pop[g] = _mm256_and_ps(can, _mm256_cmp_ps(lhs, rhs, _CMP_GE_OQ));
          any = _mm256_or_ps(any, pop[g]);
        }
        if (_mm256_testz_ps(any, any)) break;
        for (int g = 0; g < G; ++g) {
          // The slot c was pushed at holds the point below it.
          const __m256i slot = _mm256_max_epi32(_mm256_cvttps_epi32(_mm256_sub_ps(vj_start, cj[g])),
                                                _mm256_setzero_si256());
          const __m256i i3 = _mm256_add_epi32(_mm256_slli_epi32(slot, kGroupShift), lane[g]);
          top[g] = _mm256_add_epi32(top[g], _mm256_castps_si256(pop[g]));  // -1 where popping
          ah[g] = _mm256_blendv_ps(ah[g], bh[g], pop[g]);
          aj[g] = _mm256_blendv_ps(aj[g], bj[g], pop[g]);
          bh[g] = _mm256_blendv_ps(bh[g], ch[g], pop[g]);
          bj[g] = _mm256_blendv_ps(bj[g], cj[g], pop[g]);
          ch[g] = _mm256_mask_i32gather_ps(ch[g], link_h, i3, pop[g], 4);
          cj[g] = _mm256_mask_i32gather_ps(cj[g], link_j, i3, pop[g], 4);
        }
      }
      if (u >= out.rec_lo && u < out.rec_hi && b0 + W >= out.v0 && b0 < out.v1) {
        // The receivers' angles, onto the texels either side (issued here, off the hull's
        // dependency chain, so they overlap the next step's pops).
        __m256 angle[G];
        for (int g = 0; g < G; ++g) {
          const __m256i has =
              _mm256_and_si256(ok[g], _mm256_cmpgt_epi32(top[g], _mm256_setzero_si256()));
          const __m256 sl = _mm256_div_ps(_mm256_sub_ps(ah[g], h[g]),
                                          _mm256_mul_ps(_mm256_sub_ps(aj[g], j), mps));
          // Nothing ahead: -inf (atan -pi/2); outside the field: 0 (weight 0, kept finite).
          const __m256 v = _mm256_blendv_ps(minus_inf, sl, _mm256_castsi256_ps(has));
          angle[g] = fast_atan8(_mm256_and_ps(v, valid[g]));
          if (clamp) angle[g] = _mm256_max_ps(angle[g], _mm256_setzero_ps());
        }
        out.add(u, b0, t, angle, valid);
      }
      // Push on the lanes inside the field: slot s keeps the old top (every lane stores; a
      // lane outside the field never reads slot s back, its top does not move).
      float* link_h_s = link_h + static_cast<std::size_t>(s) * W;
      float* link_j_s = link_j + static_cast<std::size_t>(s) * W;
      for (int g = 0; g < G; ++g) {
        _mm256_storeu_ps(link_h_s + 8 * g, ah[g]);
        _mm256_storeu_ps(link_j_s + 8 * g, aj[g]);
        top[g] = _mm256_sub_epi32(top[g], _mm256_castps_si256(valid[g]));  // +1 where valid
        ch[g] = _mm256_blendv_ps(ch[g], bh[g], valid[g]);
        cj[g] = _mm256_blendv_ps(cj[g], bj[g], valid[g]);
        bh[g] = _mm256_blendv_ps(bh[g], ah[g], valid[g]);
        bj[g] = _mm256_blendv_ps(bj[g], aj[g], valid[g]);
        ah[g] = _mm256_blendv_ps(ah[g], h[g], valid[g]);
        aj[g] = _mm256_blendv_ps(aj[g], j, valid[g]);
      }
    }
  }
#endif
  if (s_take == steps)
    take_hull(cg, u_start, u_end - frame.step, j_start, link_h, link_j, regs, *keep);
}

#ifdef PENUMBRA_SWEEP_LANES_AVX512
// Accumulator::add with the sixteen angles in one vector: texels b0 .. b0 + 15 in one step
// (lane m takes t times lane m - 1's angle, then 1 - t times its own), then b0 + 16 .. b0 + 23
// as add()'s last vector (lane 15's angle below texel b0 + 16): the same floats into the same
// slots.
[[gnu::always_inline]] inline void add16(const Accumulator& out, int u, int b0, float t,
                                         const __m512& angle, __mmask16 valid) {
  const std::size_t q = static_cast<std::size_t>(u - out.u0) * out.row + (b0 - out.v0 + kAccPad);
  float* a = out.acc + q;
  out.t_of_u[u - out.u0] = t;
  const __m512i up = _mm512_setr_epi32(15, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14);
  const __m512 below = _mm512_maskz_permutexvar_ps(0xfffe, up, angle);
  const __m512 w_hi = _mm512_maskz_mov_ps(static_cast<__mmask16>(valid << 1), _mm512_set1_ps(t));
  const __m512 w_lo = _mm512_maskz_mov_ps(valid, _mm512_set1_ps(1.0f - t));
  _mm512_storeu_ps(a,
                   _mm512_fmadd_ps(w_lo, angle, _mm512_fmadd_ps(w_hi, below, _mm512_loadu_ps(a))));
  // Slot 16 (add()'s last vector changes no other slot: it adds 0 * 0 to them, and an
  // accumulator is never -0).
  const float angle15 =
      _mm512_cvtss_f32(_mm512_maskz_permutexvar_ps(kAll, _mm512_set1_epi32(15), angle));
  a[16] = std::fma((valid >> 15) ? t : 0.0f, angle15, a[16]) + 0.0f;
}

void Sweep::samples16(int cg, int s_begin, int steps, int u_start, LaneScratch& sc) const {
  constexpr int W = kGroupLines;
  std::int32_t* const step_b0 = sc.step_b0.data();
  std::int32_t* const step_ok = sc.step_ok.data();
  float* const step_t = sc.step_t.data();
  float* const step_h = sc.step_h.data();
  const int step = frame.step, last = bmax;
  // Eight steps a vector: base = cg + slope u (one multiply-add, as the scalar pass compiles),
  // b0 = floor(base), t = base - b0; inside the field are the lanes l with 0 <= b0 + l < bmax,
  // and b0 + l = bmax where t = 0 (as AzimuthFrame::height_at): lanes [lo, hi) of the mask.
  const __m256i eight = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m512d slope = _mm512_set1_pd(frame.slope), c = _mm512_set1_pd(cg);
  const __m256i zero = _mm256_setzero_si256(), sixteen = _mm256_set1_epi32(W);
  const __m256i one = _mm256_set1_epi32(1), vlast = _mm256_set1_epi32(last);
  const __mmask8 k8 = 0xff;  // maskz forms: GCC 12 warns on the unmasked ones' undefined source
  for (int s = s_begin; s < steps; s += 8) {
    const __m256i u = _mm256_sub_epi32(_mm256_set1_epi32(u_start - s * step),
                                       _mm256_mullo_epi32(eight, _mm256_set1_epi32(step)));
    const __m512d base = _mm512_fmadd_pd(_mm512_maskz_cvtepi32_pd(k8, u), slope, c);
    const __m512d down =
        _mm512_maskz_roundscale_pd(k8, base, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m256i b0 = _mm512_maskz_cvttpd_epi32(k8, down);
    const __m256 t = _mm512_maskz_cvtpd_ps(k8, _mm512_sub_pd(base, down));
    const __m256i on_last =
        _mm256_maskz_mov_epi32(_mm256_cmp_ps_mask(t, _mm256_setzero_ps(), _CMP_EQ_OQ), one);
    const __m256i lo =
        _mm256_min_epi32(_mm256_max_epi32(_mm256_sub_epi32(zero, b0), zero), sixteen);
    const __m256i hi = _mm256_min_epi32(
        _mm256_max_epi32(_mm256_add_epi32(_mm256_sub_epi32(vlast, b0), on_last), zero), sixteen);
    const __m256i mask = _mm256_max_epi32(
        _mm256_sub_epi32(_mm256_sllv_epi32(one, hi), _mm256_sllv_epi32(one, lo)), zero);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(step_b0 + s), b0);
    _mm256_storeu_ps(step_t + s, t);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(step_ok + s), mask);
  }
  const __m512 scale16 = _mm512_set1_ps(scale);
  for (int s = s_begin, u = u_start - s_begin * step; s < steps; ++s, u -= step) {
    const int b0 = step_b0[s];
    if (b0 + W - 1 < 0 || b0 > last) continue;  // no lane inside the field
    const float* col = heights + static_cast<std::ptrdiff_t>(u) * stride + kPad + b0;
    const __m512 h0 = _mm512_loadu_ps(col), h1 = _mm512_loadu_ps(col + 1);
    _mm512_storeu_ps(step_h + static_cast<std::size_t>(s) * W,
                     _mm512_mul_ps(scale16, _mm512_fmadd_ps(_mm512_set1_ps(step_t[s]),
                                                            _mm512_sub_ps(h1, h0), h0)));
  }
}

template <class Take>
void Sweep::walk16(const LaneScratch& sc, int s_begin, int steps, int s_take, int u_start,
                   float j_start, const Accumulator& out, float* links, HullRegisters& regs,
                   Take take) const {
  constexpr int W = kGroupLines;
  static_assert(W == 16 && kVectors == 2);
  // Between the 8-lane registers and 512-bit ones through memory (entry, exit, a hull taken).
  HullLanes lanes;
  lanes.store(regs);
  __m512i t16 = _mm512_load_si512(lanes.size);
  __m512 a_h = _mm512_load_ps(lanes.p[0]), a_j = _mm512_load_ps(lanes.p[1]);
  __m512 b_h = _mm512_load_ps(lanes.p[2]), b_j = _mm512_load_ps(lanes.p[3]);
  __m512 c_h = _mm512_load_ps(lanes.p[4]), c_j = _mm512_load_ps(lanes.p[5]);
  // A fourth point, d, below c, and per lane how many of a, b, c, d are current (the rest are
  // refilled from the links only when a pop needs them: at least min(size, 3) are current).
  __m512 d_h = c_h, d_j = c_j;
  const __m512i two = _mm512_set1_epi32(2), three = _mm512_set1_epi32(3),
                four = _mm512_set1_epi32(4);
  __m512i depth = _mm512_maskz_min_epi32(kAll, t16, three);
  auto split = [&] {  // back into the 8-lane registers
    _mm512_store_si512(lanes.size, t16);
    _mm512_store_ps(lanes.p[0], a_h), _mm512_store_ps(lanes.p[1], a_j);
    _mm512_store_ps(lanes.p[2], b_h), _mm512_store_ps(lanes.p[3], b_j);
    _mm512_store_ps(lanes.p[4], c_h), _mm512_store_ps(lanes.p[5], c_j);
    lanes.load_into(regs);
  };
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i one = _mm512_set1_epi32(1), zero_i = _mm512_setzero_si512();
  // Pairs (h, j) from the two gathers' halves, and interleaved for the links.
  const __m512i evens =
      _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odds = _mm512_add_epi32(evens, one);
  const __m512i pairs_lo =
      _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  const __m512i pairs_hi = _mm512_add_epi32(pairs_lo, _mm512_set1_epi32(8));
  const __m512 zero = _mm512_setzero_ps(), vj_start = _mm512_set1_ps(j_start);
  const __m512 mps = _mm512_set1_ps(frame.metres_per_step);
  const __m512 minus_inf = _mm512_set1_ps(-std::numeric_limits<float>::infinity());
  for (int s = s_begin, u = u_start - s_begin * frame.step; s < steps; ++s, u -= frame.step) {
    if (s == s_take) {
      split();
      take(u);
    }
    const int b0 = sc.step_b0[s];
    if (b0 + W - 1 < 0 || b0 > bmax) continue;
    const std::size_t at = static_cast<std::size_t>(s) * W;
    const __mmask16 valid = static_cast<__mmask16>(sc.step_ok[s]);
    const __m512 h = _mm512_loadu_ps(sc.step_h.data() + at);
    const __m512 j = _mm512_set1_ps(static_cast<float>(frame.step * u));
    // Pop while the second point is at least as steep as the top (Timonen 2010, sec. 4). The
    // second round's test is made here, beside the first, off the rounds' chain: on the lanes
    // the first round pops, b against c (current wherever the hull holds three points), the
    // points that pop moves into a and b; the same products, so the same floats
    // (docs/terrain_shadow_log.md, "Twenty-fourth round").
    const __mmask16 second = _mm512_mask_cmp_ps_mask(
        _mm512_mask_cmpgt_epi32_mask(valid, t16, two),
        _mm512_mul_ps(_mm512_sub_ps(c_h, h), _mm512_sub_ps(b_j, j)),
        _mm512_mul_ps(_mm512_sub_ps(b_h, h), _mm512_sub_ps(c_j, j)), _CMP_GE_OQ);
    __mmask16 popped = 0;  // the last round's pops
    for (int round = 0;; ++round) {
      __mmask16 pop;
      if (round == 1) {
        pop = popped & second;
      } else {
        const __mmask16 can = _mm512_mask_cmpgt_epi32_mask(valid, t16, one);
        const __m512 lhs = _mm512_mul_ps(_mm512_sub_ps(b_h, h), _mm512_sub_ps(a_j, j));
        const __m512 rhs = _mm512_mul_ps(_mm512_sub_ps(a_h, h), _mm512_sub_ps(b_j, j));
        pop = _mm512_mask_cmp_ps_mask(can, lhs, rhs, _CMP_GE_OQ);
      }
      popped = pop;
      // Written before the pop, beside the comparison (off the path from it to the gather;
      // docs/terrain_shadow_log.md, "Tenth round"; GCC 12 sinks the index into the refill path,
      // and kept here it measured the same: "Twenty-first round"): the lanes whose c a pop leaves
      // stale with a point below b (depth < 4, size > 3 before it), and the links' index of c's
      // slot (c becomes b, and the slot b was pushed at holds the point below it; the gather reads
      // refilling lanes only, whose c is a point of the hull).
      const __mmask16 low =
          _mm512_mask_cmplt_epi32_mask(_mm512_cmpgt_epi32_mask(t16, three), depth, four);
      const __m512i i3 = _mm512_add_epi32(
          _mm512_maskz_slli_epi32(
              kAll, _mm512_maskz_cvttps_epi32(kAll, _mm512_sub_ps(vj_start, c_j)), kGroupShift),
          lane);
      if (pop == 0) break;
      t16 = _mm512_mask_sub_epi32(t16, pop, t16, one);
      depth = _mm512_mask_sub_epi32(depth, pop, depth, one);
      a_h = _mm512_mask_mov_ps(a_h, pop, b_h), a_j = _mm512_mask_mov_ps(a_j, pop, b_j);
      b_h = _mm512_mask_mov_ps(b_h, pop, c_h), b_j = _mm512_mask_mov_ps(b_j, pop, c_j);
      c_h = _mm512_mask_mov_ps(c_h, pop, d_h), c_j = _mm512_mask_mov_ps(c_j, pop, d_j);
      // Lanes whose c is now stale with a point below b: c from b's link.
      const __mmask16 refill = pop & low;
      if (refill == 0) continue;
      // Up to eight refilling lanes (nearly every refill: one lane in 40%, two in 22%), their
      // links' indices packed into the low lanes: one 8-element gather instead of two (a gather
      // costs the same with any mask, about 2.4 ns of this CPU's throughput), the pairs
      // expanded back into the refilling lanes.
      const int n_refill = __builtin_popcount(refill);
      if (n_refill <= 8) {
        const __m512i packed = _mm512_maskz_compress_epi32(refill, i3);
        const __m512 g = _mm512_castsi512_ps(_mm512_mask_i32gather_epi64(
            zero_i, static_cast<__mmask8>(_bzhi_u32(0xff, static_cast<unsigned>(n_refill))),
            _mm512_maskz_extracti32x8_epi32(0xff, packed, 0), links, 8));
        c_h = _mm512_mask_expand_ps(c_h, refill, _mm512_maskz_permutexvar_ps(kAll, evens, g));
        c_j = _mm512_mask_expand_ps(c_j, refill, _mm512_maskz_permutexvar_ps(kAll, odds, g));
        depth = _mm512_mask_mov_epi32(depth, refill, three);
        continue;
      }
      // Each link's (height, j) pair as one 64-bit element, lanes 0-7 then 8-15.
      const __m512 lo = _mm512_castsi512_ps(
          _mm512_mask_i32gather_epi64(zero_i, static_cast<__mmask8>(refill),
                                      _mm512_maskz_extracti32x8_epi32(0xff, i3, 0), links, 8));
      const __m512 hi = _mm512_castsi512_ps(
          _mm512_mask_i32gather_epi64(zero_i, static_cast<__mmask8>(refill >> 8),
                                      _mm512_maskz_extracti32x8_epi32(0xff, i3, 1), links, 8));
      c_h = _mm512_mask_mov_ps(c_h, refill, _mm512_permutex2var_ps(lo, evens, hi));
      c_j = _mm512_mask_mov_ps(c_j, refill, _mm512_permutex2var_ps(lo, odds, hi));
      depth = _mm512_mask_mov_epi32(depth, refill, three);
    }
    if (u >= out.rec_lo && u < out.rec_hi && b0 + W >= out.v0 && b0 < out.v1) {
      const __mmask16 has = _mm512_mask_cmpgt_epi32_mask(valid, t16, zero_i);
      const __m512 sl =
          _mm512_div_ps(_mm512_sub_ps(a_h, h), _mm512_mul_ps(_mm512_sub_ps(a_j, j), mps));
      // Nothing ahead: -inf (atan -pi/2); outside the field: 0 (weight 0, kept finite).
      __m512 angle = _mm512_maskz_mov_ps(valid, _mm512_mask_blend_ps(has, minus_inf, sl));
      fast_atan16(angle);
      if (clamp) angle = _mm512_maskz_max_ps(kAll, angle, zero);
      add16(out, u, b0, sc.step_t[s], angle, valid);
    }
    // Push on the lanes inside the field: slot s keeps the old top (every lane stores).
    _mm512_storeu_ps(links + 2 * at, _mm512_permutex2var_ps(a_h, pairs_lo, a_j));
    _mm512_storeu_ps(links + 2 * at + W, _mm512_permutex2var_ps(a_h, pairs_hi, a_j));
    if (valid == kAll) {  // every lane inside the field (most steps): register moves, no blends
      t16 = _mm512_add_epi32(t16, one);
      depth = _mm512_maskz_min_epi32(kAll, _mm512_add_epi32(depth, one), four);
      d_h = c_h, d_j = c_j, c_h = b_h, c_j = b_j, b_h = a_h, b_j = a_j, a_h = h, a_j = j;
      continue;
    }
    t16 = _mm512_mask_add_epi32(t16, valid, t16, one);
    depth = _mm512_mask_min_epi32(depth, valid, _mm512_add_epi32(depth, one), four);
    d_h = _mm512_mask_mov_ps(d_h, valid, c_h), d_j = _mm512_mask_mov_ps(d_j, valid, c_j);
    c_h = _mm512_mask_mov_ps(c_h, valid, b_h), c_j = _mm512_mask_mov_ps(c_j, valid, b_j);
    b_h = _mm512_mask_mov_ps(b_h, valid, a_h), b_j = _mm512_mask_mov_ps(b_j, valid, a_j);
    a_h = _mm512_mask_mov_ps(a_h, valid, h), a_j = _mm512_mask_mov_ps(a_j, valid, j);
  }
  split();
}
#endif

}  // namespace

void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane) {
  const Sweep sw(f, fields, p, phi);
  const AzimuthFrame& frame = sw.frame;
  const int u0 = frame.x_major ? r.x0 : r.y0, u1 = frame.x_major ? r.x1 : r.y1;
  const int v0 = frame.x_major ? r.y0 : r.x0, v1 = frame.x_major ? r.y1 : r.x1;
  const int row = (v1 - v0) + 2 * kAccPad;
  // The pass below leaves acc's texels zeroed; all of it is zeroed here when its shape changed.
  const std::size_t size = static_cast<std::size_t>(u1 - u0) * row;
  if (sc.acc.size() != size || sc.acc_row != row) sc.acc.assign(size, 0.0f);
  sc.acc_row = row;
  sc.t_of_u.resize(static_cast<std::size_t>(u1 - u0));
  // Lines b = c + slope * u with integer c bracketing every texel of the region.
  const double lo = std::min(v0 - frame.slope * u0, v0 - frame.slope * (u1 - 1));
  const double hi = std::max((v1 - 1) - frame.slope * u0, (v1 - 1) - frame.slope * (u1 - 1));
  const int c_lo = static_cast<int>(std::floor(lo)) - 1, c_hi = static_cast<int>(std::ceil(hi)) + 1;
  const int u_near = frame.step > 0 ? u0 : u1 - 1;  // sweep down to the region's near edge
  for (int cg = Sweep::group_of(c_lo); cg <= c_hi; cg += kGroupLines)
    sw.run_group(cg, u_near, Accumulator{sc.acc.data(), sc.t_of_u.data(), u0, v0, v1, row, u0, u1},
                 sc);

  // acc / weight, 8 x 8 blocks at a time (transposed in registers where u is x), zeroing acc
  // behind for the next azimuth (its padding collects what lanes outside the region add, and is
  // never read while the rows keep their shape).
  const int w = r.width(), nu = u1 - u0, nv = v1 - v0, bmax = sw.bmax;
  float* acc = sc.acc.data() + kAccPad;
  const float* t_of_u = sc.t_of_u.data();
  auto value = [&](int u, int v) {
    const std::size_t i = static_cast<std::size_t>(u) * row + v;
    const float wt = texel_weight(v0 + v, bmax, t_of_u[u]);
    return wt > 0 ? acc[i] / wt : 0.0f;
  };
  auto at = [&](int u, int v) {  // plane index of (u, v), relative to the region
    return frame.x_major ? static_cast<std::size_t>(v) * w + u
                         : static_cast<std::size_t>(u) * w + v;
  };
  if (!frame.x_major) {
    // u is y: a row of acc is a row of the plane. Inside the field the weight is t + (1 - t),
    // which rounds to 1 (a / 1 = a): rows whose weight does are copied, their first and last
    // texels of the field (one-sided weights) by value().
    for (int u = 0; u < nu; ++u) {
      float* a = acc + static_cast<std::size_t>(u) * row;
      float* dst = plane + at(u, 0);
      const float t = t_of_u[u];
      if (!interior_weight_is_one(t)) {
        for (int v = 0; v < nv; ++v) dst[v] = value(u, v), a[v] = 0.0f;
        continue;
      }
      const bool first = v0 == 0, last = v1 - 1 == bmax;
      const float first_value = first ? value(u, 0) : 0.0f;
      const float last_value = last ? value(u, nv - 1) : 0.0f;
      int v = 0;  // copied and zeroed in one pass
#ifdef PENUMBRA_SWEEP_LANES_AVX512
      for (; v + 16 <= nv; v += 16) {
        _mm512_storeu_ps(dst + v, _mm512_loadu_ps(a + v));
        _mm512_storeu_ps(a + v, _mm512_setzero_ps());
      }
#endif
      for (; v + 8 <= nv; v += 8) {
        _mm256_storeu_ps(dst + v, _mm256_loadu_ps(a + v));
        _mm256_storeu_ps(a + v, _mm256_setzero_ps());
      }
      for (; v < nv; ++v) dst[v] = a[v], a[v] = 0.0f;
      if (first) dst[0] = first_value;
      if (last) dst[nv - 1] = last_value;
    }
    return;
  }
  // u is x: 8 x 8 blocks transposed in registers. Where the block's eight columns' weight
  // t + (1 - t) rounds to 1 a block is copied (rows outer, so that the plane's writes run along
  // eight rows; acc, read across, is in cache from the walk); the field's first and last rows
  // (one-sided weights) are worked out first by value() and written over the copies after.
  const int nu8 = nu / 8 * 8, nv8 = nv / 8 * 8;
  sc.unit.resize(static_cast<std::size_t>(nu8 / 8));  // per 8 columns: weights round to 1
  for (int u = 0; u < nu8; u += 8) {
    bool unit = true;
    for (int i = 0; i < 8; ++i) unit &= interior_weight_is_one(t_of_u[u + i]);
    sc.unit[static_cast<std::size_t>(u / 8)] = unit;
  }
  const bool first = v0 == 0 && nv8 > 0, last = v1 - 1 == bmax && nv - 1 < nv8;
  sc.edge_values.resize(2 * static_cast<std::size_t>(nu8));
  float* const first_values = sc.edge_values.data();
  float* const last_values = first_values + nu8;
  for (int u = 0; u < nu8; ++u) {
    if (first) first_values[u] = value(u, 0);
    if (last) last_values[u] = value(u, nv - 1);
  }
  auto block8 = [&](int v, int u) {
    __m256 m[8];
    for (int i = 0; i < 8; ++i) {
      const std::size_t q = static_cast<std::size_t>(u + i) * row + v;
      m[i] = _mm256_loadu_ps(acc + q);
      _mm256_storeu_ps(acc + q, _mm256_setzero_ps());
    }
    if (!sc.unit[static_cast<std::size_t>(u / 8)])  // acc / weight
      for (int i = 0; i < 8; ++i) {
        const float t = t_of_u[u + i];
        alignas(32) float wl[8];
        for (int l = 0; l < 8; ++l) wl[l] = texel_weight(v0 + v + l, bmax, t);
        const __m256 b = _mm256_load_ps(wl);
        m[i] = _mm256_and_ps(_mm256_div_ps(m[i], b),
                             _mm256_cmp_ps(b, _mm256_setzero_ps(), _CMP_GT_OQ));
      }
    transpose8(m);
    for (int i = 0; i < 8; ++i) _mm256_storeu_ps(plane + at(u, v + i), m[i]);
  };
  int vb = 0;
#ifdef PENUMBRA_SWEEP_LANES_AVX512
  // 16 x 16 blocks where both halves' columns copy: a third fewer shuffles per float than two
  // 8 x 8 transposes (1-3% of the sweep: docs/terrain_shadow_log.md, "Twenty-second round").
  for (; vb + 16 <= nv8; vb += 16)
    for (int u = 0; u < nu8; u += 8) {
      if (u + 16 <= nu8 && sc.unit[static_cast<std::size_t>(u / 8)] &&
          sc.unit[static_cast<std::size_t>(u / 8) + 1]) {
        __m512 m[16];
        for (int i = 0; i < 16; ++i) {
          const std::size_t q = static_cast<std::size_t>(u + i) * row + vb;
          m[i] = _mm512_loadu_ps(acc + q);
          _mm512_storeu_ps(acc + q, _mm512_setzero_ps());
        }
        transpose16(m);
        for (int i = 0; i < 16; ++i) _mm512_storeu_ps(plane + at(u, vb + i), m[i]);
        u += 8;
        continue;
      }
      block8(vb, u);
      block8(vb + 8, u);
    }
#endif
  for (; vb < nv8; vb += 8)
    for (int u = 0; u < nu8; u += 8) block8(vb, u);
  for (int u = 0; u < nu8; ++u) {
    if (first) plane[at(u, 0)] = first_values[u];
    if (last) plane[at(u, nv - 1)] = last_values[u];
  }
  for (int u = 0; u < nu; ++u) {
    for (int v = u < nu8 ? nv8 : 0; v < nv; ++v) {
      plane[at(u, v)] = value(u, v);
      acc[static_cast<std::size_t>(u) * row + v] = 0.0f;
    }
  }
}

std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed,
                                        std::vector<GroupHull>* hulls, EditBand* band) {
  const Sweep sw(f, fields, p, azimuth_angle(k, p.azimuths));
  const AzimuthFrame& frame = sw.frame;
  // The edit box's columns [ua, ub] and rows [v0, v1) in (major, minor). Line c's sample at
  // column u lies at b = c + slope u and reads rows floor(b) and floor(b) + 1, so the lines the
  // edit changes are those with y0 - 1 <= b < y1 at a box column: c in [l0, l1), the extremes at
  // the box's first and last columns.
  const int ua = frame.x_major ? edited.x0 : edited.y0,
            ub = (frame.x_major ? edited.x1 : edited.y1) - 1;
  const int v0 = frame.x_major ? edited.y0 : edited.x0, v1 = frame.x_major ? edited.y1 : edited.x1;
  const double l0 = std::min(v0 - 1 - frame.slope * ua, v0 - 1 - frame.slope * ub);
  const double l1 = std::max(v1 - frame.slope * ua, v1 - frame.slope * ub);
  // A texel between lines floor(x) and floor(x) + 1 (x = v - slope u) changes when either does:
  // x in [l0 - 1, l1 + 1). Those texels, and both their lines, are recomputed.
  const int c_first = static_cast<int>(std::floor(l0)) - 1;
  const int c_last = static_cast<int>(std::ceil(l1)) + 1;
  const int major = frame.major_size, minor = frame.minor_size;
  const int row = minor + 2 * kAccPad;
  if (sc.acc.size() < static_cast<std::size_t>(major) * row)
    sc.acc.resize(static_cast<std::size_t>(major) * row);
  sc.acc_row = 0;  // not left zeroed
  sc.t_of_u.resize(static_cast<std::size_t>(major));
  // Texels whose two lines are both in [c_first, c_last]: c_first <= v - slope u < c_last.
  auto texel_range = [&](int u, int& lo, int& hi) {
    lo = std::max(static_cast<int>(std::ceil(c_first + frame.slope * u)), 0);
    hi = std::min(static_cast<int>(std::ceil(c_last + frame.slope * u)), minor);  // exclusive
  };
  // A sample's horizon depends on its own column and those ahead of it (along +step) only, so
  // texels ahead of the box keep theirs bit for bit: the lines are swept whole (the hull needs
  // what lies ahead) but only the columns from the near border up to the box are recorded.
  const int u_lo = frame.step > 0 ? 0 : ua, u_hi = frame.step > 0 ? ub + 1 : major;  // box too
  for (int u = u_lo; u < u_hi; ++u) {
    int lo, hi;
    texel_range(u, lo, hi);
    for (int v = lo; v < hi; ++v) {
      sc.acc[static_cast<std::size_t>(u) * row + v + kAccPad] = 0;
    }
  }
  const int u_near = frame.step > 0 ? 0 : major - 1;
  for (int cg = Sweep::group_of(c_first); cg <= c_last; cg += kGroupLines) {
    GroupHull* keep = nullptr;
    if (hulls) {
      auto it = std::find_if(hulls->begin(), hulls->end(),
                             [cg](const GroupHull& g) { return g.cg == cg; });
      if (it == hulls->end()) {
        GroupHull g;
        g.cg = cg;
        it = hulls->insert(it, std::move(g));
      }
      keep = &*it;
    }
    sw.run_group(cg, u_near,
                 Accumulator{sc.acc.data(), sc.t_of_u.data(), 0, 0, minor, row, u_lo, u_hi}, sc,
                 keep);
  }

  // The recomputed values, eight texels of a column at a time (texel_weight's and the division's
  // floats, in lanes), into the records: each comparison loads a record, a row apart.
  std::size_t pairs = 0;
  const std::size_t n_az = static_cast<std::size_t>(out.azimuths), w = f.width;
  const std::size_t rec_u = frame.x_major ? n_az : w * n_az,
                    rec_v = frame.x_major ? w * n_az : n_az;
  const std::size_t flag_u = frame.x_major ? 1 : w, flag_v = frame.x_major ? w : 1;
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 zero = _mm256_setzero_ps();
  EditBand* kept_band = band;  // null from here on where this edit keeps none
  const bool from_band =
      band && band->valid && band->grid == out.angles.data() && band->edited == edited;
  std::size_t band_at = 0;
  if (kept_band && !from_band) {
    std::size_t total = 0;
    for (int u = u_lo; u < u_hi; ++u) {
      int lo, hi;
      texel_range(u, lo, hi);
      if (lo < hi) total += static_cast<std::size_t>(hi - lo) + 8;
    }
    // Kept for edits whose lines cover at most an eighth of the field (a brush's): a larger one
    // would hold a copy of that much of the grid for little gain. Memory: at most an eighth of
    // the horizons.
    if (total > static_cast<std::size_t>(major) * minor / 8) {
      *kept_band = EditBand{};
      kept_band = nullptr;
    } else {
      kept_band->values.resize(total);
      kept_band->edited = edited, kept_band->grid = out.angles.data(), kept_band->valid = true;
    }
  }
  for (int u = u_lo; u < u_hi; ++u) {
    int lo, hi;
    texel_range(u, lo, hi);
    if (lo >= hi) continue;
    pairs += static_cast<std::size_t>(hi - lo);
    const float t = sc.t_of_u[u];
    // texel_weight(v): (0 + (v >= 1 ? t : 0)) + (v < bmax || t == 0 ? 1 - t : 0)
    const __m256 below = _mm256_set1_ps(t), above = _mm256_set1_ps(1.0f - t);
    const __m256i one = _mm256_set1_epi32(1), bmax = _mm256_set1_epi32(sw.bmax);
    const __m256i t_zero = _mm256_set1_epi32(t == 0.0f ? -1 : 0);
    const float* acc = sc.acc.data() + static_cast<std::size_t>(u) * row + kAccPad;
    float* rec = out.angles.data() + u * rec_u + static_cast<std::size_t>(k);
    unsigned char* flag = changed + u * flag_u;
    for (int v = lo; v < hi; v += 8) {
      const __m256i vi = _mm256_add_epi32(_mm256_set1_epi32(v), iota);
      const __m256 has_below = _mm256_castsi256_ps(
          _mm256_or_si256(_mm256_cmpgt_epi32(vi, one), _mm256_cmpeq_epi32(vi, one)));
      const __m256 has_above =
          _mm256_castsi256_ps(_mm256_or_si256(_mm256_cmpgt_epi32(bmax, vi), t_zero));
      const __m256 wt = _mm256_add_ps(_mm256_add_ps(zero, _mm256_and_ps(has_below, below)),
                                      _mm256_and_ps(has_above, above));
      alignas(32) float a[8];
      const __m256 value = _mm256_and_ps(_mm256_div_ps(_mm256_loadu_ps(acc + v), wt),
                                         _mm256_cmp_ps(wt, zero, _CMP_GT_OQ));
      _mm256_store_ps(a, value);
      const int n = std::min(8, hi - v);
      if (kept_band) {
        float* kept = kept_band->values.data() + band_at;
        band_at += static_cast<std::size_t>(n);
        if (from_band) {
          const unsigned differ = static_cast<unsigned>(_mm256_movemask_ps(
                                      _mm256_cmp_ps(_mm256_loadu_ps(kept), value, _CMP_NEQ_UQ))) &
                                  ((1u << n) - 1u);
          for (unsigned m = differ; m != 0; m &= m - 1) {
            const int l = std::countr_zero(m);
            const std::size_t vl = static_cast<std::size_t>(v + l);
            kept[l] = a[l];
            rec[vl * rec_v] = a[l];
            std::atomic_ref<unsigned char>(flag[vl * flag_v]).store(1, std::memory_order_relaxed);
          }
          continue;
        }
        _mm256_storeu_ps(kept, value);
      }
      for (int l = 0; l < n; ++l) {
        const std::size_t vl = static_cast<std::size_t>(v + l);
        float& dst = rec[vl * rec_v];
        if (dst != a[l]) {
          dst = a[l];
          std::atomic_ref<unsigned char>(flag[vl * flag_v]).store(1, std::memory_order_relaxed);
        }
      }
    }
  }
  return pairs;
}

}  // namespace PENUMBRA_SWEEP_KERNELS

#ifndef PENUMBRA_SWEEP_LANES_AVX512
namespace avx512 {  // sweep_lanes_avx512.cpp
void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane);
std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed,
                                        std::vector<GroupHull>* hulls, EditBand* band);
}  // namespace avx512

namespace {

std::optional<SweepIsa>& forced_isa() {
  static std::optional<SweepIsa> forced;
  return forced;
}

}  // namespace

SweepIsa sweep_isa() {
  // x86-64-v4's AVX-512 subsets, those the AVX-512 copy is compiled for.
  static const bool avx512 =
      __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  if (forced_isa() && (*forced_isa() == SweepIsa::kAvx2 || avx512)) return *forced_isa();
  return avx512 ? SweepIsa::kAvx512 : SweepIsa::kAvx2;
}

void force_sweep_isa(std::optional<SweepIsa> isa) {
  forced_isa() = isa;
}

void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane) {
  if (sweep_isa() == SweepIsa::kAvx512)
    avx512::sweep_direction_lanes(f, fields, p, r, phi, sc, plane);
  else
    avx2::sweep_direction_lanes(f, fields, p, r, phi, sc, plane);
}

void sweep_azimuth_lanes(const data::HeightField& f, const LaneFields& fields,
                         const HorizonParams& p, const TexelRect& r, int k, LaneScratch& sc,
                         float* plane) {
  sweep_direction_lanes(f, fields, p, r, azimuth_angle(k, p.azimuths), sc, plane);
}

std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed,
                                        std::vector<GroupHull>* hulls, EditBand* band) {
  return sweep_isa() == SweepIsa::kAvx512
             ? avx512::sweep_azimuth_lines_through(f, fields, p, edited, k, sc, out, changed, hulls,
                                                   band)
             : avx2::sweep_azimuth_lines_through(f, fields, p, edited, k, sc, out, changed, hulls,
                                                 band);
}
#endif

}  // namespace penumbra::terrain_shadow::detail

#endif  // __AVX2__
