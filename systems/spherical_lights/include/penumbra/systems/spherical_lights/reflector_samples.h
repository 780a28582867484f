// Surface sample points of spherical lights (SLs), found offline with the sphere fit
// ([Guerrero08] sec. 4.2): every sphere of an object's set is also a light that re-emits what the
// object's surface reflects, and these are the points whose reflection it re-emits.
//
// Per SL S_i, rays leave its centre in the geodesic directions w_j (geodesic_directions:
// frequency 3 gives 92, [Guerrero08] sec. 8.6). The surface segment P_Si is the set of surface
// points nearest S_i by eq. 2, d(p, S) = |p - x_S| / r_S. Per direction, the three ray cases:
//  1. back-side hits (the triangle faces away from the centre) inside P_Si: the farthest one;
//  2. back-side hits, none inside P_Si: no point (another SL covers that direction);
//  3. no back-side hit (the centre is outside the object): the nearest front-side hit of the
//     opposite ray, if inside P_Si; else no point.
// Then, [Guerrero08] sec. 6.2: a direction whose point on S_i (x_i + r_i w_j) lies inside another
// sphere of the same set has no point: the SL emits nothing there, so the intersecting spheres'
// mutual occlusion is precomputed and ignored at run time.
// Each point keeps its position, normal (interpolated vertex normal, facing out) and albedo (the
// mesh's base colour: MeshData carries no textures, so the points sample it exactly and the
// cube-map pass of sec. 4.2 is not needed). Rays test every triangle (no BVH): an offline step,
// about 10^7 ray-triangle tests a second per core.
//
// Errors: std::invalid_argument naming the mesh for no triangles, a non-finite position, an
// index out of range; naming the sphere for a non-finite centre or a radius that is not finite
// and > 0. A sphere that finds no point is valid (it then emits nothing).
// Threading: pure function; runs the SLs in parallel in the caller's TBB arena.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/mesh.h"
#include "penumbra/data/reflector_samples.h"
#include "penumbra/data/sphere_set.h"

namespace penumbra::spherical_lights {

// Vertices of the geodesic sphere of `frequency` >= 1 (icosahedron faces cut into frequency^2
// triangles): 10 f^2 + 2 unit directions, deterministic order.
std::vector<glm::vec3> geodesic_directions(int frequency);

struct ReflectorSettings {
  int geodesic_frequency = 3;  // 92 directions per SL ([Guerrero08] sec. 8.6)
};

using data::ReflectorSamples;  // engine/data: plain data, shared by the Reflector component
using data::SphereSamples;

// Samples for `spheres` (the object's fitted set; roots and children alike are SLs) on `mesh`
// (closed, outward winding). `albedo_override`, when its components are >= 0, replaces the mesh's
// base colour (a tinted model).
ReflectorSamples sample_reflector(const data::MeshData& mesh, std::span<const data::Sphere> spheres,
                                  const ReflectorSettings& settings = {},
                                  glm::vec3 albedo_override = glm::vec3(-1.0f));

}  // namespace penumbra::spherical_lights
