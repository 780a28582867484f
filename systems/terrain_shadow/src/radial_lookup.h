// Internal: RadialHorizonSweep::horizons16's lookup (radial_horizon_sweep.cpp), compiled for
// AVX-512 by radial_lookup_avx512.cpp and chosen at run time (sweep_lanes.h's sweep_isa()).
#pragma once

namespace penumbra::terrain_shadow::detail {

// One side of a RadialHorizonSweep (its Side, read only): groups of 8 lines, each `columns` x 8
// lane-interleaved angles (NaN outside the field).
struct RadialSideView {
  const float* angle;
  int columns, lines, j_lo, u_first, sign;
  bool x_major;
  float lines_per_slope;
};

namespace avx512 {
// horizons8's floats, written to out[l], for those of the sixteen texels (x0 + l, y), l < 16,
// that lie on side `index` of the foot (at (foot_x, foot_y) cells; side.lines >= 2) inside its
// columns with both lines beside them finite; returns their lanes (bit l: out[l] written). The
// others are horizon()'s to answer.
unsigned radial_horizons16(const RadialSideView& side, int index, float foot_x, float foot_y,
                           int x0, int y, float* out);
}  // namespace avx512

}  // namespace penumbra::terrain_shadow::detail
