// Multi-scale horizon marching on the height pyramid ([Meier13] eq. 4.5-4.14,
// local lights eq. 4.22-4.25; GPU details sec. 5.2).
// [Interface fixed by the system.]
//
// Along each azimuth, sample i (i = 0..n-1) sits at distance d_i cells, d_0 = 1 and spacing
// d_{i+1} - d_i = sr^i (sr = 2^(1/ls)), and reads pyramid level clamp(ceil(i - ls * lo), 0,
// n - 1) (eq. 4.14): the level filtered for 1 / 2^lo of the sample spacing. The thesis writes
// i + ls * lo with its level index running the other way; here level 0 is the finest, so a
// larger lo reads finer levels and is sharper (tests: the error against brute force falls
// with lo). The sample's elevation is atan of the height difference to the receiver over the
// plane distance (eq. 4.5-4.6); the receiver height is level 0 at the texel (not the sample's
// level as in eq. 4.5: equally accurate for lo >= 2, more accurate below). The angles are
// joined by a uniform cubic B-spline (eq. 4.8-4.12) whose maximum (eq. 4.13) is taken over the
// knots and the mid-points (weights 1/6 2/3 1/6 and 1/48 23/48 23/48 1/48, sec. 5.2); its ends
// repeat the first and last samples. Samples whose bilinear footprint leaves the field are
// dropped; no sample at all gives 0 (clamp_at_zero) or -pi/2. For a local light
// (limit_to_point set) only samples up to the first one beyond the light's plane distance are
// used (eq. 4.24) and the maximum is taken up to the light's distance (eq. 4.25), the spline
// also evaluated there; nothing in range (light within one cell) gives -pi/2.
//
// Cost: per texel and azimuth one bilinear lookup and one atan per sample inside the field
// (17 on average at 256 x 256 with ls = 4; about half that with ls = 2). Threading:
// single-threaded; calls for disjoint regions may run concurrently on the same `out` once it has
// the field's size (only then is it not resized).
#pragma once

#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

struct MarchParams {
  float level_offset = 2.0f;  // lo >= 0, finite ([Meier13] eq. 4.14): larger = sharper, more aliasing
};

// Horizons of `region` from a pyramid built with the same height_scale as params.height_scale
// (the pyramid's own scale is used). `out` is resized to the whole field if its size differs.
// Throws std::invalid_argument naming the field (pyramid.source()) for an unbuilt pyramid,
// fewer than 3 azimuths, a non-finite height scale or light position, a bad level offset or a
// region outside the field.
void march_horizons(const HeightPyramid& pyramid, const HorizonParams& params,
                    const MarchParams& march, const TexelRect& region, HorizonGrid& out);

}  // namespace penumbra::terrain_shadow
