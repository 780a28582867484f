// TerrainHorizons: what the terrain shadow system publishes of a terrain's horizons, for debug
// views and overlays (the terrain demo draws the wedges of the texel under the cursor). Added
// and removed with TerrainShadowState; both pointers share ownership of the system's
// TerrainShadowing, whose contents change in place when terrain_shadow.visibility updates them:
// read them in systems ordered after it (declare reads<TerrainHorizons>()).
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

struct TerrainHorizons {
  std::shared_ptr<const HorizonGrid> horizons;            // per texel and azimuth (radians)
  std::shared_ptr<const std::vector<glm::vec3>> normals;  // per texel, unit
};

}  // namespace penumbra::terrain_shadow
