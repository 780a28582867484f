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
// horizons8's floats for the sixteen texels (x0 + l, y), l < 16, all on `side` (the caller
// checks) with the foot at (foot_x, foot_y) cells and side.lines >= 2: false (out untouched)
// where a texel's column is outside the side or a line beside it is NaN.
bool radial_horizons16(const RadialSideView& side, float foot_x, float foot_y, int x0, int y,
                       float* out);
}  // namespace avx512

}  // namespace penumbra::terrain_shadow::detail
