// Dynamic blockers as sets of spheres ([Giraud] sec. 4.2, [Guerrero08] sec. 4.1): a plain
// component of an entity with a Transform. The blocker accumulation system moves the spheres to
// world space each frame (penumbra/systems/blocker_accumulation/). Fitted sets are read from
// sphere files (engine/assets: sphere_file.h, written by ./penumbra spheres).
#pragma once

#include <memory>
#include <vector>

#include "penumbra/data/sphere_set.h"

namespace penumbra::components {

// centre (in the entity's local frame: Transform applies), radius, parent (-1: a root).
using Sphere = data::Sphere;

// Shared and immutable, like MeshInstance's mesh: many entities may use one fitted set.
struct SphereSet {
  std::shared_ptr<const std::vector<Sphere>> spheres;
};

}  // namespace penumbra::components
