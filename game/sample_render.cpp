#include "penumbra/game/sample_render.h"

#include <cmath>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/motion.h"
#include "penumbra/components/terrain.h"
#include "penumbra/data/height_field.h"
#include "penumbra/game/sample_world.h"
#include "penumbra/render/packet.h"
#include "penumbra/systems/render_extract/render_extract.h"

namespace penumbra::game {
namespace {
using components::Camera;
using components::DebugPoints;
using components::DebugSphere;
using components::FrameTime;
using components::Position;

constexpr float kTerrainDepth = -62.0f;  // below the particle box (|z| <= 50)

float terrain_height(float x, float y) {
  return 6.0f * std::sin(0.045f * x) * std::cos(0.035f * y) +
         3.0f * std::sin(0.11f * x + 0.07f * y) + 0.0004f * (x * x + y * y);
}

// Sun and sky on the CPU: albedo-free lighting per height sample (what terrain_shadow will
// replace with horizon-based visibility).
std::shared_ptr<std::vector<glm::vec3>> light_terrain(const data::HeightField& f,
                                                      const render::Sky& sky) {
  auto out = std::make_shared<std::vector<glm::vec3>>(f.heights.size());
  const glm::vec3 sun = glm::normalize(sky.sun_direction);
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const float dx = f.at(std::min(x + 1, f.width - 1), y) - f.at(std::max(x - 1, 0), y);
      const float dy = f.at(x, std::min(y + 1, f.height - 1)) - f.at(x, std::max(y - 1, 0));
      const glm::vec3 n = glm::normalize(glm::vec3(-dx, -dy, 2.0f * f.cell_size));
      const float direct = std::max(glm::dot(n, sun), 0.0f);
      const glm::vec3 ambient = glm::mix(sky.ground, sky.zenith, 0.5f + 0.5f * n.z);
      (*out)[static_cast<std::size_t>(y) * f.width + x] =
          1.1f * direct * glm::vec3(1.0f, 0.95f, 0.85f) + 0.25f * ambient;
    }
  }
  return out;
}
}  // namespace

void populate_sample_scene(ecs::World& world, const SampleSceneConfig& config) {
  systems::emplace_render_resources(world);
  world.emplace_resource<Camera>();
  systems::RenderSettings& settings = world.resource<systems::RenderSettings>();
  settings.view.point_size = 1.0f;
  settings.view.exposure_ev = 0.0f;

  auto field = std::make_shared<data::HeightField>();
  field->width = field->height = config.terrain_size;
  field->cell_size = 1.0f;
  field->source = "sample world terrain";
  const float half = 0.5f * static_cast<float>(config.terrain_size - 1);
  for (int y = 0; y < field->height; ++y)
    for (int x = 0; x < field->width; ++x)
      field->heights.push_back(
          terrain_height(static_cast<float>(x) - half, static_cast<float>(y) - half));
  auto lighting = light_terrain(*field, settings.sky);
  world.create_with(components::Terrain{field, {-half, -half, kTerrainDepth}, {0.38f, 0.42f, 0.3f}},
                    components::TerrainLighting{lighting, field->width, field->height, nullptr});
  // Debug geometry filled each frame: the particles as points, each light as a wire sphere.
  world.create_with(DebugPoints{});
  if (const SampleLights* lights = world.try_resource<SampleLights>())
    for (std::size_t i = 0; i < lights->count; ++i) world.create_with(DebugSphere{});
}

void add_sample_render_systems(jobs::Schedule& s, const SampleSceneConfig& config) {
  s.add_task("orbit_camera",
             [](jobs::SystemContext& ctx) {
               const FrameTime& t = ctx.world().resource<const FrameTime>();
               Camera& c = ctx.world().resource<Camera>();
               const float a = -1.5707963f + 0.05f * static_cast<float>(t.elapsed);
               c.position = {190.0f * std::cos(a), 190.0f * std::sin(a), 45.0f};
               c.target = {0.0f, 0.0f, -15.0f};
               c.vertical_fov = 0.85f;
               c.far_plane = 1000.0f;
             })
      .reads<FrameTime>()
      .writes<Camera>();

  const float gain = config.particle_gain;
  const std::size_t max_points = config.max_points;
  s.add_task(
       "extract_particles",
       [gain, max_points](jobs::SystemContext& ctx) {
         ecs::World& w = ctx.world();
         auto q = w.query<const Position, const Irradiance>();
         q.prepare();
         const std::size_t n = q.entity_count();
         const std::size_t step =
             max_points == 0 || n <= max_points ? 1 : (n + max_points - 1) / max_points;
         w.query<DebugPoints>().each([&](DebugPoints& out) {
           out.points.clear();
           std::size_t i = 0;
           q.each([&](const Position& p, const Irradiance& e) {
             if (i++ % step != 0) return;
             out.points.push_back(
                 {{p.x, p.y, p.z}, {gain * e.r + 0.02f, gain * e.g + 0.02f, gain * e.b + 0.02f}});
           });
         });
       })
      .reads<Position, Irradiance>()
      .writes<DebugPoints>();

  s.add_task(
       "extract_lights",
       [](jobs::SystemContext& ctx) {
         const SampleLights& l = ctx.world().resource<const SampleLights>();
         std::size_t i = 0;
         ctx.world().query<DebugSphere>().each([&](DebugSphere& sphere) {
           if (i >= l.count) return;
           const PointLight& p = l.lights[i++];
           const glm::vec3 c(p.r, p.g, p.b);
           sphere = {{p.x, p.y, p.z}, 2.0f, c / std::max(1.0f, std::max(c.x, std::max(c.y, c.z)))};
         });
       })
      .reads<SampleLights>()
      .writes<DebugSphere>();

  systems::add_render_extract(s);
}

}  // namespace penumbra::game
