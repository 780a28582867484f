// Internal: one group of kRadialLanes (8) neighbouring lines of RadialHorizonSweep (one side of
// the foot), swept together. The lines share their columns (r = r_near + k is the same on every
// line of a side), so a group steps column by column with each line on a vector lane: the two
// heights either side of each line's crossing are gathered, the hulls pop on masked lanes (as in
// sweep_lanes.h) and the group's slopes land in one lane-interleaved block. The scalar kernel
// does the same arithmetic one line at a time (the fallback without AVX2, and the tests'
// reference: both give the same floats).
#pragma once

#include <array>
#include <vector>

namespace penumbra::terrain_shadow::detail {

inline constexpr int kRadialLanes = 8;

// What one group needs (RadialHorizonSweep::run fills it). Line l of the group crosses column k
// at v = v0 + (r_near + k) m[l], in samples of the side's minor axis; lanes past the side's last
// line have first == end == 0.
struct RadialGroup {
  const float* heights = nullptr;  // the field, row-major
  int stride_u = 1, stride_v = 1;  // element strides of the major and minor axes
  int size_v = 0;                  // samples along the minor axis
  int u_first = 0, sign = 1;       // column k is major coordinate u_first + sign k
  double v0 = 0, r_near = 0;
  float height_scale = 1;
  int width = 0;  // columns written: [0, width) of every lane
  std::array<double, kRadialLanes> m{};
  std::array<float, kRadialLanes> inv_metres{};  // 1 / (sqrt(1 + m^2) cell size)
  std::array<int, kRadialLanes> first{}, end{};  // columns swept: [first, end)
};

// Per-thread scratch: the hulls, kRadialLanes floats per depth (the AVX-512 pair walk: (h, r)
// pairs of sixteen lanes in hull_h); the lanes' samples (heights and active masks) per column.
struct RadialScratch {
  std::vector<float> hull_r, hull_h;
  std::vector<float> h, active;
};

// Writes block[k * kRadialLanes + l] for k in [0, g.width): the slope (tan of the elevation) of
// the horizon of line l's sample at column k towards the foot, -inf with nothing in between,
// NaN outside [first[l], end[l]).
void sweep_radial_group_scalar(const RadialGroup& g, RadialScratch& sc, float* block);
void sweep_radial_group_lanes(const RadialGroup& g, RadialScratch& sc, float* block);
// Two groups of one side, each into its block, with the same floats as two
// sweep_radial_group_lanes calls: where the AVX-512 copy runs, as one walk of sixteen lanes
// (lanes 0-7 group a, 8-15 group b: one chain of pop rounds for both). A group of width 0
// (lanes first == end == 0) is not written; its block may then be null.
void sweep_radial_pair_lanes(const RadialGroup& a, const RadialGroup& b, RadialScratch& sc,
                             float* block_a, float* block_b);

}  // namespace penumbra::terrain_shadow::detail
