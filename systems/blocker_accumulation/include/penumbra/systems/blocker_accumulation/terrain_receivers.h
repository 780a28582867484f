// Blockers' shadows on a height field's texels: the texels within some blocker's reach (its
// influence radius, blocker_grid.h) are shaded with the terrain's own log-SH wedge visibility
// (from its horizons, [Giraud] eq. 15-23) and the blockers' log-SH summed, then one exponential
// ([Giraud] sec. 4.2: terrain and blockers shadow together).
//
// The terrain system's lighting stays the base: each reached texel is scaled by
//   ratio = E(terrain + blockers) / E(terrain alone),
// both computed the same way (log-SH wedges, exponential, product with the clamped cosine, dot
// with the environment), so where the blockers' influence fades out the ratio is exactly 1 and
// no seam shows between reached and untouched texels. The ratio scales the whole texel value,
// local lights' share included (their own visibility through blockers is not modelled here).
// Texels whose terrain-only irradiance is below 1e-6 of the environment's keep their value.
//
// Threading: shade_terrain_receivers is a pure function of its arguments; it runs
// tbb::parallel_for over reached rows.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/terrain_shadow/horizon.h"
#include "penumbra/systems/terrain_shadow/log_wedge.h"

namespace penumbra::blocker_accumulation {

struct TerrainReceivers {
  const data::HeightField* field = nullptr;
  glm::vec3 origin{0.0f};  // world position of sample (0, 0) at height 0
  float height_scale = 1;
  const terrain_shadow::HorizonGrid* horizons = nullptr;  // environment horizons, per texel
  const std::vector<glm::vec3>* normals = nullptr;        // per texel, unit
};

struct TerrainShadeStats {
  std::size_t reached = 0;  // texels within some blocker's reach
  std::size_t changed = 0;  // of those, texels whose value changed
};

// The texel rectangle (half-open) some blocker can reach, or empty.
terrain_shadow::TexelRect reached_texels(const TerrainReceivers& t, const WorldSphere& s,
                                         float min_sin);

// The per-texel ratio E(terrain + blockers) / E(terrain) (1 where no blocker reaches or the
// blockers' summed log-visibility averages above -0.005; faded in up to -0.01, about 1%).
// Shaded on the lattice of every `stride`-th texel along x and y (and the last row and column),
// the texels between bilinear in the lattice's ratios; of the lattice rows, those with
// (y / stride) % period == phase are recomputed and the others keep their values (spreading the
// work over `period` frames; only the texels between recomputed lattice rows are interpolated
// again). `ratio` is reset to 1 when its size is not the field's.
template <int N>
TerrainShadeStats update_terrain_ratios(const TerrainReceivers& t,
                                        const BlockerAccumulation<N>& blockers,
                                        const terrain_shadow::LogWedge<N>& wedges,
                                        const sh::CoeffsRgb<N>& radiance,
                                        std::vector<glm::vec3>& ratio, int phase = 0,
                                        int period = 1, int stride = 1);

// `base` (the terrain system's per-texel lighting) with the blockers' shadows applied: every
// row's ratio computed now.
template <int N>
std::vector<glm::vec3> shade_terrain_receivers(const TerrainReceivers& t,
                                               const BlockerAccumulation<N>& blockers,
                                               const terrain_shadow::LogWedge<N>& wedges,
                                               const sh::CoeffsRgb<N>& radiance,
                                               const std::vector<glm::vec3>& base,
                                               TerrainShadeStats* stats = nullptr);

}  // namespace penumbra::blocker_accumulation
