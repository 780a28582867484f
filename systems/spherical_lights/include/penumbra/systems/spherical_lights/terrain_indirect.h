// One-bounce light from spherical lights on a height field's texels: colour bleeding onto the
// ground near reflecting objects ([Guerrero08] eq. 14 at each texel, the terrain's own normal).
// Only texels within some light's reach are shaded: where its sin(angular radius) is above
// `min_sin` (reached_texels of the blocker system, terrain_receivers.h); the others are zero.
// The work is spread over frames as the blockers' terrain shadow does: of the reached rows,
// those with y % period == phase are recomputed, the others keep their value. Texels no light
// reaches any more are set to zero at once.
// Threading: a pure function of its arguments; tbb::parallel_for over the rows it recomputes.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/blocker_accumulation/terrain_receivers.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"

namespace penumbra::spherical_lights {

// `indirect`: per texel irradiance (W/m^2), resized (and zeroed) to the field's size. Returns
// the texels within reach.
template <int N>
std::size_t update_terrain_indirect(const blocker_accumulation::TerrainReceivers& t,
                                    const SphereLightGather<N>& gather, float min_sin,
                                    std::vector<glm::vec3>& indirect, int phase = 0,
                                    int period = 1);

}  // namespace penumbra::spherical_lights
