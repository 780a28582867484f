#include "penumbra/game/boulders.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/assets/gltf.h"
#include "penumbra/assets/load_error.h"
#include "penumbra/assets/mesh_simplify.h"
#include "penumbra/assets/sphere_file.h"
#include "penumbra/assets/sphere_fit.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/reflector.h"
#include "penumbra/components/reflector_radiance.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "terrain_height.h"

namespace penumbra::game {
namespace {

using components::FrameTime;
using components::Terrain;
using components::Transform;

// The model's sphere set: from the cache when it holds a valid fit of this model with this
// count, else fitted now (and cached).
std::vector<data::Sphere> sphere_set(const data::MeshData& mesh, const std::string& name, int count,
                                     const std::string& cache_dir) {
  std::filesystem::path cached;
  if (!cache_dir.empty()) {
    cached = std::filesystem::path(cache_dir) / (name + "_" + std::to_string(count) + ".psph");
    try {
      if (std::filesystem::exists(cached)) {
        assets::SphereSetFile f = assets::load_sphere_file(cached);
        if (f.spheres.size() == static_cast<std::size_t>(count)) return std::move(f.spheres);
      }
    } catch (const assets::LoadError&) {
      // corrupt or stale: fitted again below, and rewritten
    }
  }
  assets::SphereFitOptions o;
  o.count = count;
  o.method = assets::SphereFitMethod::kVariational;  // under a second; half k-means' Er
  o.surface_samples = 4096;
  o.volume_cells = 16384;
  o.eval_samples = 1 << 14;
  o.coverage_samples = 1 << 12;
  const assets::SphereFitResult fit = assets::fit_spheres(mesh, o);
  if (!cached.empty()) {
    std::filesystem::create_directories(cached.parent_path());
    assets::write_sphere_file(cached, assets::to_sphere_file(fit, name));
  }
  return fit.spheres;
}

void roll(ecs::World& w) {
  const float t = static_cast<float>(w.resource<const FrameTime>().elapsed);
  const Terrain* terrain = nullptr;
  w.query<const Terrain>().each([&](const Terrain& x) {
    if (!terrain && x.heights) terrain = &x;
  });
  w.query<const Boulder, Transform>().each([&](const Boulder& b, Transform& out) {
    const float a = b.phase + b.speed * t / b.path_radius;  // angle along the circle
    const glm::vec2 xy = b.path_radius * glm::vec2(std::cos(a), std::sin(a));
    const float ground = terrain ? terrain_height(*terrain, xy) : 0.0f;
    // Rolling without slipping: turned by distance / radius about the horizontal axis at right
    // angles to the motion.
    const glm::vec3 forward =
        glm::vec3(-std::sin(a), std::cos(a), 0.0f) * (b.speed >= 0 ? 1.0f : -1.0f);
    const glm::vec3 axis = glm::cross(glm::vec3(0, 0, 1), forward);
    const float turned = std::abs(b.speed) * t / b.radius;
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(xy, ground + b.radius));
    m = glm::rotate(m, turned, axis);
    m = glm::scale(m, glm::vec3(b.scale));
    out.world = glm::translate(m, -b.model_centre);
  });
}

// Three great circles (16 segments each) per sphere of every boulder's set, in world space.
void draw_spheres(ecs::World& w) {
  const bool on = w.resource<const BoulderView>().spheres;
  w.query<const Boulder, const components::SphereSet, const Transform, components::DebugLines>()
      .each([&](const Boulder&, const components::SphereSet& set, const Transform& t,
                components::DebugLines& out) {
        out.lines.clear();
        if (!on || !set.spheres) return;
        const float scale = glm::length(glm::vec3(t.world[0]));
        constexpr int kSegments = 16;
        for (const data::Sphere& s : *set.spheres) {
          const glm::vec3 c = glm::vec3(t.world * glm::vec4(s.centre, 1.0f));
          const float r = s.radius * scale;
          for (int axis = 0; axis < 3; ++axis) {
            glm::vec3 prev{};
            for (int k = 0; k <= kSegments; ++k) {
              const float a = 2 * std::numbers::pi_v<float> * k / kSegments;
              glm::vec3 q(0.0f);
              q[(axis + 1) % 3] = r * std::cos(a);
              q[(axis + 2) % 3] = r * std::sin(a);
              if (k > 0) out.lines.push_back({prev, c + q, {0.3f, 2.0f, 3.0f}});
              prev = c + q;
            }
          }
        }
      });
}

}  // namespace

void populate_boulders(ecs::World& world, const std::string& data_dir,
                       const BoulderConfig& config) {
  world.emplace_resource<BoulderView>(BoulderView{config.show_spheres});
  if (config.count <= 0) return;
  struct Model {
    std::shared_ptr<const data::MeshData> mesh;
    std::shared_ptr<const std::vector<data::Sphere>> spheres;
    std::shared_ptr<const std::vector<glm::vec3>> points, normals;
    glm::vec3 centre{0.0f};
    float radius = 1;
  };
  std::vector<Model> models;
  for (const char* name : {"bunny", "suzi"}) {
    const std::filesystem::path file =
        std::filesystem::path(data_dir) / "models" / (std::string(name) + ".glb");
    auto mesh = std::make_shared<data::MeshData>(assets::merge_instances(assets::load_gltf(file)));
    Model m;
    m.spheres = std::make_shared<const std::vector<data::Sphere>>(
        sphere_set(*mesh, name, config.spheres, config.cache_dir));
    // Bounding sphere of the set: centre of its box, radius to the farthest sphere surface.
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const data::Sphere& s : *m.spheres) {
      lo = glm::min(lo, s.centre - s.radius);
      hi = glm::max(hi, s.centre + s.radius);
    }
    m.centre = 0.5f * (lo + hi);
    m.radius = 0;
    for (const data::Sphere& s : *m.spheres)
      m.radius = std::max(m.radius, glm::length(s.centre - m.centre) + s.radius);
    if (config.simplify_error > 0)  // drawn and shaded small (the spheres fit the full mesh)
      *mesh = assets::simplify_mesh(*mesh, {0.1f, config.simplify_error}).mesh;
    m.points = std::make_shared<const std::vector<glm::vec3>>(mesh->positions);
    m.normals = std::make_shared<const std::vector<glm::vec3>>(data::vertex_normals(*mesh));
    m.mesh = std::move(mesh);
    models.push_back(std::move(m));
  }
  const Terrain* terrain = nullptr;
  world.query<const Terrain>().each([&](const Terrain& x) {
    if (!terrain && x.heights) terrain = &x;
  });
  const float extent =
      terrain ? terrain->heights->cell_size * (terrain->heights->width - 1) : 20000.0f;
  ecs::Entity pair_leader{};
  for (int i = 0; i < config.count; ++i) {
    const Model& m = models[i % 3 == 2 ? 1 : 0];  // bunny, bunny, Suzanne, ...
    Boulder b;
    b.path_radius = extent * (0.12f + 0.3f * static_cast<float>(i) / config.count);
    b.phase = 2.4f * static_cast<float>(i);  // golden-angle-ish spread
    b.speed = (i % 2 ? 1.0f : -1.0f) * (150.0f + 20.0f * static_cast<float>(i % 5));
    b.radius = config.radius * (0.8f + 0.4f * static_cast<float>(i % 3) / 2.0f);
    b.scale = b.radius / m.radius;
    b.model_centre = m.centre;
    b.model = i % 3 == 2 ? 1 : 0;
    glm::vec3 albedo = i % 2 ? glm::vec3(0.62f, 0.55f, 0.45f) : glm::vec3(0.5f, 0.5f, 0.52f);
    if (i < config.reflectors && config.reflectors >= 2 && i < 2) {
      // The colour-bleeding pair: red ahead, white on the next circle out, side by side.
      albedo = i == 0 ? glm::vec3(0.85f, 0.08f, 0.04f) : glm::vec3(0.85f, 0.85f, 0.85f);
      if (i == 1) {
        const Boulder& first = *world.get<Boulder>(pair_leader);
        b.path_radius = first.path_radius + first.radius + b.radius * 1.15f;
        b.phase = first.phase;
        b.speed = first.speed * b.path_radius / first.path_radius;  // same angular speed
      }
    }
    const ecs::Entity e = world.create_with(
        b, Transform{}, components::MeshInstance{m.mesh}, components::Material{albedo, 0.0f},
        components::SphereSet{m.spheres}, components::Receiver{m.points, m.normals},
        components::ReceiverLighting{}, components::VertexLighting{}, components::DebugLines{});
    if (i == 0) pair_leader = e;
    if (i < config.reflectors) {
      // [Guerrero08] sec. 4.2: sample points on the drawn (simplified) mesh, tinted.
      auto samples = std::make_shared<const data::ReflectorSamples>(
          spherical_lights::sample_reflector(*m.mesh, *m.spheres, {}, albedo));
      world.add(e, components::Reflector{std::move(samples)});
      world.add(e, components::ReflectorRadiance{});
    }
  }
}

void add_boulder_systems(jobs::Schedule& schedule, bool roll_on_circles) {
  if (roll_on_circles)
    schedule.add_task("demo_boulders", [](jobs::SystemContext& ctx) { roll(ctx.world()); })
        .reads<FrameTime, Terrain, Boulder>()
        .writes<Transform>();
  schedule
      .add_task("demo_boulder_spheres", [](jobs::SystemContext& ctx) { draw_spheres(ctx.world()); })
      .reads<Boulder, components::SphereSet, Transform, BoulderView>()
      .writes<components::DebugLines>();
}

}  // namespace penumbra::game
