// What the blocker and spherical-light tuners share about a scene's objects (docs/tune.md): the
// ground receivers under each object, the objects' fitted spheres in world space, and the
// reference scene of their meshes under the scene's sky.
// Threading: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/sphere_set.h"
#include "penumbra/reference/scene.h"
#include "tune_scene.h"

namespace penumbra::tune {

// Receivers facing up on a 12 x 12 grid under each object, 1.25 object radii to each side of
// its ground point: where its shadow and its bounce fall.
std::vector<glm::vec3> ground_receivers(const TuneScene& scene);

// `count` spheres fitted to the object's model (k-means, assets/sphere_fit.h), in world space.
std::vector<data::Sphere> fit_world_spheres(const TuneObject& object, int count,
                                            std::uint64_t seed);

// The objects' meshes (with their albedos) under the scene's environment, for the reference.
reference::SceneDesc object_scene(const TuneScene& scene);

}  // namespace penumbra::tune
