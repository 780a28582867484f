// Internal: the line sweep eight lines at a time on AVX2 lanes (horizon_sweep.cpp chooses it
// when the build targets AVX2, the project's default x86-64-v3).
//
// Lines c, c+1, ..., c+7 of one azimuth cross column u at minor coordinates base + l with the
// same fraction t, so their samples are eight consecutive heights of a column (two unaligned
// loads from a copy of the field whose minor axis is contiguous), their hull updates run as
// masked vector steps (pops without branches per line), and their receivers scatter into eight
// consecutive texels. Same samples and same arithmetic as the scalar sweep, so results agree
// with brute_force_horizons(kSweepLines) to float precision (tested).
#pragma once

#include <cstddef>
#include <vector>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow::detail {

// The field twice, each with the minor axis of one kind of azimuth contiguous and 8 samples of
// zero padding on either side: x_major[x * stride_x + 8 + y], y_major[y * stride_y + 8 + x].
struct LaneFields {
  std::vector<float> x_major, y_major;
  int stride_x = 0, stride_y = 0;
  explicit LaneFields(const data::HeightField& f);
};

struct LaneScratch {
  std::vector<float> acc, weight;     // (major, minor + padding) layout
  std::vector<float> hull_h, hull_j;  // [depth * 8 + lane]
  std::vector<float> slope;           // recorded receivers: [record * 8 + lane]
  std::vector<int> rec_u, rec_b;
  std::vector<float> rec_t;
  std::vector<unsigned char> rec_valid;  // lane bits
};

// Azimuth k of the region into `plane` (region-sized, row-major in x, y): the contract of the
// scalar sweep_azimuth in horizon_sweep.cpp.
void sweep_azimuth_lanes(const data::HeightField& f, const LaneFields& fields,
                         const HorizonParams& p, const TexelRect& r, int k, LaneScratch& sc,
                         float* plane);
// The same along any azimuth phi (radians): a key light's horizons (sweep_direction_horizons).
void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane);

// Recomputes azimuth k of every texel whose sweep lines pass within a sample of `edited`,
// exactly as a full sweep_horizons would, writing `out` (sized to the field) and setting
// changed[y * width + x] = 1 where a value changed (relaxed atomic stores: several azimuths
// may run concurrently). Returns the number of (texel, azimuth) pairs recomputed.
std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed);

}  // namespace penumbra::terrain_shadow::detail
