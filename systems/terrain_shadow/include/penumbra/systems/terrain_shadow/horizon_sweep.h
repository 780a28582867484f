// Exact horizons by line sweep (Timonen and Westerholm 2010, "Scalable Height Field
// Self-Shadowing"), and the brute-force ray march it is tested against.
//
// For each azimuth the field is covered by parallel lines one cell apart along the minor axis.
// Each line is sampled where it crosses the major axis's grid lines (for an x-major azimuth:
// at every integer x), the height there interpolated linearly between the two samples of that
// column: the exact terrain on those grid lines, no pyramid, no filtering. Sweeping a line from
// its far end towards the receivers while keeping the upper convex hull of the samples already
// passed gives every sample's horizon exactly, in amortised O(1) per sample. A texel's horizon
// is then interpolated linearly between the two lines that pass either side of it in its
// column (less than a cell apart; exact for azimuths along the axes and diagonals, where a line
// passes through every texel).
//
// Cost: about width * height samples per azimuth, each a few compares; on AVX2 sixteen lines
// run per step as masked vector operations, in a copy compiled for AVX-512 where the CPU has it
// (src/sweep_lanes.h). Memory: per task, 8 or 16 azimuths'
// planes of the region and one line group's hull. Threading: pure function of its inputs; calls for
// disjoint regions or different outputs may run concurrently (each with its own SweepWorkspace).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

// The sweep's buffers kept from one call to the next: a caller that sweeps again and again (the
// terrain system, at every update and edit) owns one, so that calls stop allocating once the
// sizes settle. It holds one plane of the region per azimuth (as many floats as the region's
// records: 8 MB at 256^2 with 32 azimuths, 256 MB at 1024^2 with 64), per thread the lane
// kernel's accumulators, and the field's two padded copies; and, after edits
// (sweep_horizons_through), each edited line group's hull at the edit, a few kB per group and
// azimuth, so that the next edit there does not walk the unchanged lines ahead of it again. Not
// thread-safe: one call at a time per workspace.
class SweepWorkspace {
 public:
  SweepWorkspace();
  ~SweepWorkspace();
  SweepWorkspace(SweepWorkspace&&) noexcept;
  SweepWorkspace& operator=(SweepWorkspace&&) noexcept;
  // The buffers are a cache: a copy starts empty, and assigning keeps this one's buffers but
  // drops what they hold about an edited grid (see set_sole_writer). The setting is copied.
  SweepWorkspace(const SweepWorkspace&);
  SweepWorkspace& operator=(const SweepWorkspace&);

  // For a caller that owns the grid it edits (TerrainShadowing does): between two
  // sweep_horizons_through calls with this workspace, their `out` is written by nothing but
  // sweeps with this workspace. Each edit then also keeps, per azimuth, the values it recomputed
  // along its lines, and the next edit of the same rectangle into the same grid compares with
  // those instead of the grid's records (a contiguous read instead of a cache line per pair;
  // the same results). Memory: for edits whose lines cover at most an eighth of the field, so at
  // most an eighth of the grid's. Off by default: a grid overwritten behind the workspace's back
  // (say copy-assigned to its state before the edit) would otherwise keep the edit's values
  // along those lines.
  void set_sole_writer(bool on) { sole_writer_ = on; }
  bool sole_writer() const { return sole_writer_; }

  struct Buffers;      // internal (horizon_sweep.cpp)
  Buffers& buffers();  // made anew after a move

 private:
  std::unique_ptr<Buffers> buffers_;
  bool sole_writer_ = false;
};

// Environment horizons (limit_to_point must be empty: a distance limit has no hull form) for
// the texels of `region`, written into `out` (resized to the whole field if its size differs).
// Lines that do not pass through `region` are skipped.
void sweep_horizons(const data::HeightField& field, const HorizonParams& params,
                    const TexelRect& region, HorizonGrid& out);
// The same, reusing `workspace`'s buffers (same results, bit for bit).
void sweep_horizons(const data::HeightField& field, const HorizonParams& params,
                    const TexelRect& region, HorizonGrid& out, SweepWorkspace& workspace);

// Horizons of the texels of `region` along one azimuth `phi` (radians, any finite value), by
// the same lines, hull and interpolation as sweep_horizons' azimuths (its kernel: sixteen lines per
// step on AVX2): a directional light's shadow. `out` gets region.count() angles, row-major
// (x fastest). O(field) for one direction. Throws as sweep_horizons, and for a non-finite phi.
void sweep_direction_horizons(const data::HeightField& field, const HorizonParams& params,
                              double phi, const TexelRect& region, std::vector<float>& out);

// The horizon seen from a plane position `start` (in cells, may be fractional) at height
// `start_height` (metres, already scaled) along azimuth `phi` (radians), sampling the terrain
// where the ray crosses the major axis's grid lines, as the sweep does: atan of the largest
// (height - start_height) / distance over samples at distance > 0 and <= max_distance (metres,
// in the plane). Samples on the ray's own start column are skipped. No samples in range:
// -pi/2 (or 0 with clamp_at_zero).
float ray_horizon(const data::HeightField& field, float height_scale, glm::vec2 start,
                  float start_height, float phi, float max_distance, bool clamp_at_zero);
// The same along the plane direction `direction` (non-zero; need not be unit) instead of an
// angle: no trigonometry (a light's cap directions, cap_horizon_direction).
float ray_horizon(const data::HeightField& field, float height_scale, glm::vec2 start,
                  float start_height, glm::vec2 direction, float max_distance, bool clamp_at_zero);

// Brute force, O(width) per texel and azimuth, for tests and as the reference of the other
// methods; honours limit_to_point.
//  - kTexelRays: ray_horizon from every texel itself: the exact horizon of the terrain
//    interpolated along the major grid lines.
//  - kSweepLines: ray_horizon from the two sweep-line points bracketing each texel, blended
//    with the sweep's weights: what the sweep computes, without the hull, so the two must agree
//    to float precision (the test of the hull; kTexelRays measures the line interpolation).
enum class BruteForceSampling { kTexelRays, kSweepLines };
void brute_force_horizons(const data::HeightField& field, const HorizonParams& params,
                          const TexelRect& region, HorizonGrid& out,
                          BruteForceSampling sampling = BruteForceSampling::kTexelRays);

// After an edit of the samples in `edited`: recomputes every (texel, azimuth) whose sweep lines
// pass within a sample of the edit -- the only horizons the edit can change -- exactly as
// sweep_horizons would, and sets changed[y * width + x] = 1 for texels whose horizons changed
// (`changed` is resized to width * height if needed; other entries are left as they are).
// `out` must hold the field's previous horizons for the same params. Returns the number of
// (texel, azimuth) pairs recomputed: about (edit size + 4) x (1 + |tan|) lines x the field's
// length per azimuth, instead of the whole field. Without AVX2: a full sweep, compared.
// With a workspace that swept or edited the previous field: the lines start from the hulls
// the last edits left where those lie at or ahead of this edit (the same bits as a walk from
// the far end); they are used only while the field differs from the workspace's last one
// inside `edited` alone, with the same azimuths and height scale, and cleared otherwise.
// With SweepWorkspace::set_sole_writer, the same rectangle edited again compares with the values
// the last edit kept instead of `out`'s records.
std::size_t sweep_horizons_through(const data::HeightField& field, const HorizonParams& params,
                                   const TexelRect& edited, HorizonGrid& out,
                                   std::vector<unsigned char>& changed);
std::size_t sweep_horizons_through(const data::HeightField& field, const HorizonParams& params,
                                   const TexelRect& edited, HorizonGrid& out,
                                   std::vector<unsigned char>& changed, SweepWorkspace& workspace);

// The same with the one-line-at-a-time kernel, whatever the build targets (sweep_horizons runs
// sixteen lines per step on AVX2 lanes where available): for tests and benchmarks.
void sweep_horizons_scalar(const data::HeightField& field, const HorizonParams& params,
                           const TexelRect& region, HorizonGrid& out);

// One texel's horizon at azimuth k exactly as the sweep computes it (kSweepLines), without the
// rest of the field: what an edit recomputes for the few (texel, azimuth) pairs it can change.
// Inputs are not validated (call validate_horizon_input once).
float sweep_line_horizon(const data::HeightField& field, const HorizonParams& params, int x, int y,
                         int k);

}  // namespace penumbra::terrain_shadow
