// Scene of the reference integrator: what occludes (height fields, triangle meshes, analytic
// spheres), what emits (an environment map, spherical lights), and exact ray queries against
// the occluders through an Embree 3 BVH (kept out of this header).
//
// Units: metres, radians; radiance in W / (m^2 sr) per RGB channel (any consistent unit works:
// results scale linearly). World frame right-handed, z up.
//
// Geometry:
//  - a height field becomes 2 triangles per cell: sample (x, y) sits at origin + (x * cell_size,
//    y * cell_size, height(x, y)); cell (x, y)-(x+1, y+1) is split along its diagonal from (x, y)
//    to (x+1, y+1). Between samples the surface is that piecewise-linear interpolation.
//  - a mesh's positions are transformed by `transform` (affine; applied as transform * (p, 1)).
//  - spheres are exact analytic spheres (Embree sphere primitives). A ray that starts inside a
//    sphere hits its far side, so a receiver inside an occluder sphere is fully occluded: all
//    its estimates are exactly zero (documented, finite result).
//  - every occluder is two-sided and opaque, and may carry a Lambertian `albedo` (linear RGB,
//    each channel in [0, 1], the same on both sides; default black: reflects nothing). Only
//    indirect_irradiance (estimators.h) reads it; occlusion ignores it.
//  - lights are emitters only: they occlude neither the environment nor one another (nor are
//    they hit by Scene::occluded).
//
// Errors: the constructor validates everything and throws std::invalid_argument naming the item
// (e.g. "spheres[2] \"rock\": radius -1 must be finite and > 0"): non-finite or non-positive
// radii, non-finite centres / origins / heights / positions / transforms, negative or non-finite
// light radiance, an albedo outside [0, 1] or not finite, mismatched array sizes, mesh indices out
// of range or not a multiple of 3, a height field smaller than 2 x 2 or with cell_size <= 0, and
// the environment map's own checks (environment.h). std::runtime_error if Embree itself fails.
// Threading: construction builds the BVH (Embree may use TBB worker threads); afterwards a Scene
// is immutable and every const member is safe to call from any number of threads.
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/reference/environment.h"

namespace penumbra::reference {

struct EnvironmentLight {
  data::EnvironmentMap map;
  float rotation_z = 0;  // radians, counter-clockwise about +z
};

struct HeightFieldInstance {
  data::HeightField field;
  glm::vec3 origin{0.0f};  // world position of sample (0, 0) at height 0
  glm::vec3 albedo{0.0f};  // Lambertian, linear RGB in [0, 1]; black reflects nothing
};

struct MeshInstance {
  data::MeshData mesh;
  glm::mat4 transform{1.0f};  // object to world
  glm::vec3 albedo{0.0f};     // as HeightFieldInstance::albedo
};

struct SphereOccluder {
  glm::vec3 center{0.0f};
  float radius = 1;
  std::string name;        // for messages; may be empty
  glm::vec3 albedo{0.0f};  // as HeightFieldInstance::albedo
};

// The first occluder along a ray (Scene::first_hit).
struct Hit {
  float distance = std::numeric_limits<float>::infinity();  // in units of |dir|; inf: none
  // Unit geometric normal of the side that was hit (dot(normal, dir) <= 0): a sphere's radial
  // direction from its centre, a triangle's face normal (of the transformed triangle), flipped
  // towards the ray's origin. Zero when nothing was hit.
  glm::vec3 normal{0.0f};
  glm::vec3 albedo{0.0f};  // of the occluder hit; black when nothing was hit
  explicit operator bool() const { return distance < std::numeric_limits<float>::infinity(); }
};

// A sphere of uniform radiance: seen from outside, every direction that meets it carries
// `radiance`. A receiver inside (or on) a light gets nothing from it (the light is culled, as
// [Guerrero08] culls spherical lights containing the receiver): finite, documented.
struct SphereLight {
  glm::vec3 center{0.0f};
  float radius = 1;
  glm::vec3 radiance{1.0f};
  std::string name;
};

struct SceneDesc {
  std::optional<EnvironmentLight> environment;
  std::vector<HeightFieldInstance> height_fields;
  std::vector<MeshInstance> meshes;
  std::vector<SphereOccluder> spheres;
  std::vector<SphereLight> lights;
};

class Scene {
 public:
  explicit Scene(const SceneDesc& desc);
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Is anything hit along origin + t dir, 0 <= t <= t_max? `dir` need not be unit length
  // (t is then in units of |dir|).
  bool occluded(const glm::vec3& origin, const glm::vec3& dir, float t_max) const;
  // Distance (in units of |dir|) to the first hit in [0, t_max], or +infinity.
  float hit_distance(const glm::vec3& origin, const glm::vec3& dir, float t_max) const;
  // The first hit in [0, t_max]: its distance, normal and albedo (see Hit); a default Hit
  // (distance +infinity) when nothing is hit. The same traversal as hit_distance.
  Hit first_hit(const glm::vec3& origin, const glm::vec3& dir, float t_max) const;

  const EnvironmentSampler* environment() const { return environment_.get(); }
  std::span<const SphereLight> lights() const { return lights_; }
  // Largest |coordinate| of the occluders' bounding box (0 when there are none): the scale
  // that ray offsets are relative to (estimators.h).
  float extent() const { return extent_; }
  std::size_t triangle_count() const { return triangles_; }
  // Does any occluder have a nonzero albedo? (If not, indirect_irradiance is exactly zero.)
  bool reflects() const { return reflects_; }

 private:
  struct Bvh;
  std::unique_ptr<Bvh> bvh_;
  std::unique_ptr<EnvironmentSampler> environment_;
  std::vector<SphereLight> lights_;
  float extent_ = 0;
  std::size_t triangles_ = 0;
  bool reflects_ = false;
};

}  // namespace penumbra::reference
