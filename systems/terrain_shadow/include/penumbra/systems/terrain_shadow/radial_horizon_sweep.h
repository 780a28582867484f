// RadialHorizonSweep: the exact horizon of every texel towards a spherical light's foot, for
// the cap shading with TerrainShadowConfig::cap_method kSweep, the default (cap_transfer.h); the
// parallel-line sweep of the environment's horizons is horizon_sweep.h.
#pragma once

#include <array>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

// Exact horizons of every texel towards one plane point, the light's foot F (the plane
// position of its centre), for terrain between the texel and F only ([Meier13] eq. 4.22 with the
// true terrain, no pyramid): a line sweep like horizon_sweep.h, with lines radiating from F
// instead of parallel. Each of the four sides of F (+x, -x, +y, -y; |slope| <= 1 about its
// major axis) has lines v = V0 + r m_j, r the major-axis distance from F, slopes m_j = j / J
// with J = ceil(the farthest column's r): lines at most a cell apart at the far border, denser
// towards F (about 2 samples per texel in all). Each line is sampled where it crosses the major
// axis's grid lines (heights interpolated linearly in that column: the exact terrain there)
// and swept outwards from F keeping the upper convex hull of the samples passed, so each
// sample's horizon towards F is the tangent to that hull: exact, amortised O(1) per sample. A
// texel's horizon interpolates (in angle) those of the two lines either side of it in its
// column, as the sweep does; a texel on a line gets exactly ray_horizon towards F (tests).
// With F outside the field, a texel beside which a line has left the field takes ray_horizon
// itself (its own ray may leave the field where the line does not).
// Memory: one float per line sample (about 2 to 4 x width x height). Threading: run() uses
// tbb::parallel_for in the caller's arena; horizon() is const and may run concurrently.
class RadialHorizonSweep {
 public:
  // `foot`: plane position (metres, relative to sample (0, 0)); any finite point, inside the
  // field or not. Inputs are not validated (validate_horizon_input). Keeps a reference to
  // `field` for horizon(). `reach` (metres): texels farther than that along the major axis of
  // their side are not swept (horizon() gives -pi/2 there); those within it get what a sweep
  // without a reach gives, bit for bit.
  // `regions` (texels, clipped to the field), when not empty: only texels in them are asked for
  // afterwards, so each line is swept only as far as the farthest of their texels it serves, and
  // lines serving none are not swept (horizon() elsewhere is unspecified); those texels get the
  // same horizons, bit for bit. A light re-shading a quarter of the tiles sweeps about that
  // share of the line samples (light_refresh.h).
  void run(const data::HeightField& field, float height_scale, glm::vec2 foot,
           float reach = std::numeric_limits<float>::infinity(),
           std::span<const TexelRect> regions = {});
  // Elevation (radians) of the horizon of texel (x, y) towards the foot; -pi/2 when no terrain
  // lies in between (the foot within a column of the texel, or outside the field).
  float horizon(int x, int y) const;
  // horizon() of the eight texels (x0 + l, y), l < 8, all inside the field, into out[l]: the
  // same floats, eight at a time where they lie on one side of the foot (AVX2).
  void horizons8(int x0, int y, float* out) const;
  // horizon() of the sixteen texels (x0 + l, y), l < 16, all inside the field: the same floats,
  // on AVX-512 (sweep_isa()) one 16-lane pass per side of the foot the run reaches (texels a pass
  // cannot answer through horizon()), else horizons8 on each half.
  void horizons16(int x0, int y, float* out) const;

 private:
  struct Side {
    bool x_major = true;
    int sign = 1;                  // direction of the major axis away from F
    int u_first = 0, columns = 0;  // first column (major coordinate) and count
    int j_lo = 0, lines = 0;       // line j_lo + l is stored at row l
    float lines_per_slope = 1;     // J
    // Groups of 8 lines (radial_sweep_lanes.h), each columns x 8 lane-interleaved; NaN outside
    // the field.
    std::vector<float> angle;
    std::vector<int> line_end;  // with regions: columns swept per line (empty: all)
    float at(int line, int k) const {
      return angle[(static_cast<std::size_t>(line >> 3) * columns + k) * 8 + (line & 7)];
    }
  };
  // Side::line_end from the regions (run()).
  void limit_lines(Side& side, std::span<const TexelRect> regions) const;
  std::array<Side, 4> sides_;
  const data::HeightField* field_ = nullptr;
  float height_scale_ = 1;
  glm::vec2 foot_{0.0f};  // in cells
  bool foot_inside_ = true;
};

}  // namespace penumbra::terrain_shadow
