#include "object_receivers.h"

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "penumbra/assets/sphere_fit.h"

namespace penumbra::tune {

std::vector<glm::vec3> ground_receivers(const TuneScene& scene) {
  constexpr int kGrid = 12;        // receivers per side under each object
  constexpr float kReach = 1.25f;  // half-width of that grid in object radii
  std::vector<glm::vec3> points;
  for (const TuneObject& o : scene.objects) {
    const float half = kReach * o.radius;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        points.push_back({o.ground.x - half + 2 * half * (i + 0.5f) / kGrid,
                          o.ground.y - half + 2 * half * (j + 0.5f) / kGrid, o.ground.z});
  }
  return points;
}

std::vector<data::Sphere> fit_world_spheres(const TuneObject& o, int count, std::uint64_t seed) {
  assets::SphereFitOptions fo;
  fo.count = count;
  fo.method = assets::SphereFitMethod::kKMeans;
  fo.surface_samples = 4096;
  fo.volume_cells = 16384;
  fo.eval_samples = 1 << 12;
  fo.coverage_samples = 1 << 10;
  fo.seed = seed;
  std::vector<data::Sphere> out;
  for (const data::Sphere& sp : assets::fit_spheres(o.local, fo).spheres)
    out.push_back({glm::vec3(o.world * glm::vec4(sp.centre, 1.0f)), o.scale * sp.radius, -1});
  return out;
}

reference::SceneDesc object_scene(const TuneScene& scene) {
  reference::SceneDesc d;
  for (const TuneObject& o : scene.objects) {
    reference::MeshInstance m;
    m.mesh = o.mesh;
    m.albedo = o.albedo;
    d.meshes.push_back(std::move(m));
  }
  d.environment = reference::EnvironmentLight{scene.environment, scene.rotation_rad()};
  return d;
}

}  // namespace penumbra::tune
