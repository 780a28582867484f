// Multi-scale horizon marching on the height pyramid (000_7ffde676d1c99e20.txt eq. 4.5-4.14,
// local lights eq. 4.22-4.25; GPU details sec. 5.2).
// [Interface fixed by the system.]
//
// Along each azimuth, sample i (i = 0..n-1) sits at distance d_i with spacing sr^i cells
// (sr = 2^(1/ls)) and reads pyramid level min(i + ls * lo, n - 1) (eq. 4.14); its elevation
// angle is atan of the multi-scale directional derivative (eq. 4.5-4.6). The angles are joined
// by a uniform cubic B-spline (eq. 4.8-4.12) whose maximum (eq. 4.13) is taken over the knots
// and the mid-points (weights 1/6 2/3 1/6 and 1/48 23/48 23/48 1/48, sec. 5.2). Samples
// outside the field are dropped. For a local light (limit_to_point set) only samples up to the
// first one beyond the light's plane distance are used (eq. 4.24) and the maximum is taken up
// to the light's distance (eq. 4.25).
#pragma once

#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

struct MarchParams {
  float level_offset = 2.0f;  // lo >= 0 (000 eq. 4.14): larger = sharper, more aliasing
};

// Horizons of `region` from a pyramid built with the same height_scale as params.height_scale
// (the pyramid's own scale is used). `out` is resized to the whole field if its size differs.
void march_horizons(const HeightPyramid& pyramid, const HorizonParams& params,
                    const MarchParams& march, const TexelRect& region, HorizonGrid& out);

}  // namespace penumbra::terrain_shadow
