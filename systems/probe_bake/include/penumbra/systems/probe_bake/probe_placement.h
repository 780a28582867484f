// Probe placement (issue 14): the uniform grid; [Sukys14] sec. 3.1 starts both of its adaptive
// methods (spawn and merge, gradient ascent: probe_adaptive.h) from it, and it is the baseline
// they are measured against.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/probe_bake/bake_scene.h"

namespace penumbra::probe_bake {

enum class PlacementMethod {
  kGrid,        // grid_points
  kSpawnMerge,  // [Sukys14] sec. 3.1.1 (spawn_merge_points)
  kGradient,    // [Sukys14] sec. 3.1.2 (gradient_points)
};

// Grid points over [min, max] every `spacing` metres per axis: n_k = floor(extent_k / spacing)
// + 1 points, the grid centred in the box (so a box whose extent is a multiple of the spacing
// gets points on its faces). x fastest, then y, then z. Throws std::invalid_argument for a
// non-positive spacing or above 4 M points.
std::vector<glm::vec3> grid_points(const ProbeVolume& volume);

}  // namespace penumbra::probe_bake
