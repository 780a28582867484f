// ProbeAnchor: where a dynamic entity samples the probe cloud and the cell it was last found in
// (systems/probe_cloud probe_systems.h, [Sukys14] sec. 3.2). The traversal system (probes.walk)
// is its only writer after creation; spawn it with the offset and the defaults.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

namespace penumbra::components {

struct ProbeAnchor {
  glm::vec3 offset{0.0f};  // sample point in the entity's object space (its origin by default)
  std::int32_t cell = -1;  // cached cell of the cloud (-1: none yet)
  std::uint64_t generation = 0;  // the cloud generation `cell` belongs to (0: none); another
                                 // generation means another cloud: the cell is not used
  glm::vec3 point{0.0f};         // the sample point (world) `cell` was found for
  std::int32_t steps = 0;        // cells the last walk stepped across (debug, statistics)
  bool fallback = false;         // the last walk needed the fallback locate
};

}  // namespace penumbra::components
