// Internal: the line sweep kGroupLines (16) lines at a time on AVX2 lanes (horizon_sweep.cpp
// chooses it when the build targets AVX2, the project's default x86-64-v3).
//
// Lines c, c+1, ..., c+15 of one azimuth cross column u at minor coordinates base + l with the
// same fraction t, so their samples are consecutive heights of a column (unaligned loads from a
// copy of the field whose minor axis is contiguous), their hull updates run as masked vector
// steps (pops without branches per line; two vectors whose dependency chains overlap), and
// their receivers scatter into consecutive texels. Same samples and same arithmetic as the
// scalar sweep, so results agree with brute_force_horizons(kSweepLines) to float precision
// (tested). The hull is kept as links through the group's steps (a push is one vector store),
// and each step's receivers go onto their texels at once (no per-group record arrays). Why 16
// lines, three hull points in registers and an AVX-512 copy: docs/terrain_shadow.md, "Speed
// toward the floors". The AVX-512 copy walks the sixteen lanes in one 512-bit vector, with four
// hull points in registers and each link's height and j side by side (one 64-bit gather element
// each; docs/terrain_shadow_log.md, "Sixth round").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow::detail {

// Lines per group: kGroupLines / 8 AVX2 vectors of neighbouring lines step together.
inline constexpr int kGroupLines = 16;

// The field twice, each with the minor axis of one kind of azimuth contiguous and kGroupLines
// samples of zero padding on either side: x_major[x * stride_x + kGroupLines + y], y_major
// likewise.
struct LaneFields {
  std::vector<float> x_major, y_major;
  int stride_x = 0, stride_y = 0;
  LaneFields() = default;
  explicit LaneFields(const data::HeightField& f) { assign(f); }
  // Reuses the vectors' storage; rows already held (same bits) are compared, not rewritten.
  void assign(const data::HeightField& f);
  // The same result as assign(f), writing only the samples whose bits differ from the copy
  // held; returns the smallest rectangle holding them (empty when none), or the whole field when
  // the shape differed (then assign(f) ran).
  TexelRect update(const data::HeightField& f);
};

// One group's hull (every lane's points, bottom to top) as it was before the walk reached
// column u: kept from one edit to the next, so that an edit whose first recorded column is at
// or behind u resumes the walk there (the samples ahead of u are unchanged; the same floats as
// a walk from the far end). docs/terrain_shadow_log.md, "Sixth round".
struct GroupHull {
  int cg = 0;       // the group's first line
  int u_start = 0;  // the walk's first column (the field's far end for this group)
  int u = 0;        // the column the hull was taken before
  bool valid = false;
  int size[kGroupLines] = {};  // points per lane
  std::vector<float> h, j;     // lane 0's points, then lane 1's, ...
};

// The values an edit recomputed along one azimuth's lines (those it compared with `out`'s
// records, in the write-back's order), kept so that the next edit of the same rectangle into the
// same grid compares with them instead of the records (one contiguous read instead of a record
// line per pair; docs/terrain_shadow_log.md, "Ninth round"). Valid while `out`'s records along the
// band are still the values held: the workspace clears it on any other sweep.
struct EditBand {
  TexelRect edited{};
  const float* grid = nullptr;  // the HorizonGrid's angles it was written into
  bool valid = false;
  std::vector<float> values;
};

struct LaneScratch {
  std::vector<float, CacheLineAllocator<float>> acc;  // (major, minor + padding) layout
  int acc_row = 0;            // > 0: acc's texels are zeros, rows of acc_row floats
  std::vector<float> t_of_u;  // per major coordinate: the lines' offset t
  // The hull's links, [step * kGroupLines + lane], and a group's samples: heights and
  // inside-the-field masks (the AVX-512 copy: one 16-bit mask per step, at [step]); per step
  // the lanes' first minor index and offset. The links and heights on cache lines, so that the
  // walk's 64-byte loads and stores of a step's sixteen lanes never split one.
  std::vector<float, CacheLineAllocator<float>> hull_h, hull_j;
  std::vector<float, CacheLineAllocator<float>> step_h;
  std::vector<std::int32_t> step_ok, step_b0;
  std::vector<float> step_t;
  std::vector<unsigned char> unit;  // the planes pass: per 8 columns, weights that round to 1
  std::vector<float> edge_values;   // the planes pass: the first and last rows' values
};

// Which copy of the kernels below runs: the AVX-512 one (the same intrinsics and floats,
// compiled for x86-64-v4 subsets, where compares and blends go through mask registers; the
// gain is measured in docs/terrain_shadow.md) where the CPU has it. force_sweep_isa (tests,
// benchmarks) picks one; kAvx512 is ignored without the CPU's support, nullopt restores the choice.
// Not to be called while a sweep runs.
enum class SweepIsa { kAvx2, kAvx512 };
SweepIsa sweep_isa();
void force_sweep_isa(std::optional<SweepIsa> isa);

// Azimuth k of the region into `plane` (region-sized, row-major in x, y): the contract of the
// scalar sweep_azimuth in horizon_sweep.cpp.
void sweep_azimuth_lanes(const data::HeightField& f, const LaneFields& fields,
                         const HorizonParams& p, const TexelRect& r, int k, LaneScratch& sc,
                         float* plane);
// The same along any azimuth phi (radians): a key light's horizons (sweep_direction_horizons).
void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane);

// Writes the planes of azimuths [k0, k1) into the records of r's texels in `out`: plane k at
// planes[k - k0] holds r's texels row-major in x, y (a region-sized plane, or one offset to the
// first of r's rows when r is a band of whole rows of it); 8 x 8 blocks transposed in registers
// when k1 - k0 is a multiple of 8.
void texel_records(const float* const* planes, const TexelRect& r, int k0, int k1,
                   HorizonGrid& out);

// Recomputes azimuth k of every texel whose sweep lines pass within a sample of `edited`,
// exactly as a full sweep_horizons would, writing `out` (sized to the field) and setting
// changed[y * width + x] = 1 where a value changed (relaxed atomic stores: several azimuths
// may run concurrently). Returns the number of (texel, azimuth) pairs recomputed. `hulls`
// (this azimuth's, may be null) holds groups' hulls from earlier edits: a group resumes from
// its hull where that is at or ahead of the edit, and leaves its hull at the edit's first
// recorded column. The caller guarantees that every kept hull's samples ahead of its column
// are those of `fields` now (horizon_sweep.cpp clears them otherwise).
// `band` (this azimuth's, may be null: only for a sole writer, SweepWorkspace::set_sole_writer)
// replaces the records as what the recomputed values are compared with where it was kept by an
// edit of the same rectangle into the same grid, and is left holding this edit's values (or
// emptied, where the edit's lines cover more than an eighth of the field).
std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed,
                                        std::vector<GroupHull>* hulls, EditBand* band = nullptr);

}  // namespace penumbra::terrain_shadow::detail
