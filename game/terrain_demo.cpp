#include "penumbra/game/terrain_demo.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>

#include <glm/geometric.hpp>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/reflector.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/render/packet.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/environment/environment_systems.h"
#include "penumbra/systems/render_extract/render_extract.h"
#include "penumbra/systems/spherical_lights/spherical_light_systems.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "penumbra/systems/terrain_shadow/terrain_horizons.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"

namespace penumbra::game {
namespace {

using components::Camera;
using components::DebugLines;
using components::DebugSphere;
using components::EnvironmentLight;
using components::FrameTime;
using components::SphericalLight;
using components::Terrain;
using components::TerrainLighting;
using terrain_shadow::TerrainHorizons;

constexpr float kFrameSeconds = kDemoStepSeconds;

std::filesystem::path data_dir(const TerrainDemoConfig& c) {
  return std::filesystem::path(c.data_dir.empty() ? std::string(PENUMBRA_SHARED_DATA) : c.data_dir);
}

float terrain_height_at(const Terrain& t, glm::vec2 world_xy) {
  const data::HeightField& f = *t.heights;
  const glm::vec2 q = (world_xy - glm::vec2(t.origin)) / f.cell_size;
  const int x = std::clamp(static_cast<int>(std::lround(q.x)), 0, f.width - 1);
  const int y = std::clamp(static_cast<int>(std::lround(q.y)), 0, f.height - 1);
  return t.origin.z + t.height_scale * f.at(x, y);
}

void animate(ecs::World& w, const TerrainDemoConfig& config) {
  const FrameTime& time = w.resource<const FrameTime>();
  const float t = static_cast<float>(time.elapsed);
  if (auto* env = w.try_resource<EnvironmentLight>())
    env->rotation_z = config.sky_rotation_speed * t;
  if (auto* rs = w.try_resource<systems::RenderSettings>())
    rs->sky.environment_rotation = config.sky_rotation_speed * t;

  w.query<Terrain>().each([&](Terrain& terrain) {
    if (!terrain.heights) return;
    const float extent = terrain.heights->cell_size * (terrain.heights->width - 1);
    // The light circles a third of the way out, 400 m above the ground under it.
    const float a = 0.15f * t;
    const glm::vec2 xy = 0.3f * extent * glm::vec2(std::cos(a), std::sin(a));
    if (config.circling_light)
      w.query<SphericalLight>().each([&](SphericalLight& l) {
        l.position = glm::vec3(xy, terrain_height_at(terrain, xy) + 400.0f);
      });
    // A brush edit every edit_interval seconds, crater and raise alternating, just behind the
    // light so its shadows change where the eye already is.
    if (config.edit_interval > 0) {
      const auto every =
          static_cast<std::uint64_t>(std::lround(config.edit_interval / kFrameSeconds));
      if (every > 0 && time.frame > 0 && time.frame % every == 0) {
        const std::uint64_t n = time.frame / every;
        terrain_shadow::Brush b;
        b.kind = n % 2 ? terrain_shadow::BrushKind::kCrater : terrain_shadow::BrushKind::kRaise;
        b.centre = 0.3f * extent * glm::vec2(std::cos(a - 0.4f), std::sin(a - 0.4f));
        b.radius = 0.06f * extent;
        b.strength = 250.0f;
        terrain_shadow::apply_brush(terrain, b);
      }
    }
  });
}

void orbit(ecs::World& w) {
  const float t = static_cast<float>(w.resource<const FrameTime>().elapsed);
  Camera& c = w.resource<Camera>();
  float extent = 20000.0f;
  w.query<const Terrain>().each([&](const Terrain& terrain) {
    if (terrain.heights) extent = terrain.heights->cell_size * (terrain.heights->width - 1);
  });
  const DemoCameraMode* mode = w.try_resource<const DemoCameraMode>();
  if (mode && mode->follow_pair) {
    // The first boulder (red; the white one rolls on the next circle out): seen from outside
    // its circle, a little ahead and above, so the white one's lit side faces the camera.
    const Boulder* lead = nullptr;
    glm::vec3 at(0.0f);
    w.query<const Boulder, const components::Transform, const components::Reflector>().each(
        [&](const Boulder& b, const components::Transform& x, const components::Reflector&) {
          if (lead && lead->path_radius <= b.path_radius) return;  // the inner one is red
          lead = &b;
          at = glm::vec3(x.world * glm::vec4(b.model_centre, 1.0f));
        });
    if (lead) {
      const glm::vec3 out = glm::normalize(glm::vec3(at.x, at.y, 0.0f) + glm::vec3(1e-3f, 0, 0));
      const glm::vec3 side = glm::cross(glm::vec3(0, 0, 1), out);
      c.position = at + 2200.0f * out + 800.0f * side + glm::vec3(0, 0, 900.0f);
      c.target = at + 350.0f * out;
      c.vertical_fov = 0.5f;
      c.near_plane = 10.0f;
      c.far_plane = 20.0f * extent;
      return;
    }
  }
  const float a = -std::numbers::pi_v<float> / 2 + 0.03f * t;
  c.position =
      glm::vec3(0.85f * extent * std::cos(a), 0.85f * extent * std::sin(a), 0.45f * extent);
  c.target = glm::vec3(0.0f, 0.0f, 0.0f);
  c.vertical_fov = 0.8f;
  c.near_plane = 10.0f;
  c.far_plane = 20.0f * extent;
}

// The texel under the probe: march the camera ray until it goes below the terrain.
bool pick_texel(const Camera& c, const HorizonProbe& probe, const Terrain& t, int& tx, int& ty) {
  const glm::vec3 fwd = glm::normalize(c.target - c.position);
  const glm::vec3 right = glm::normalize(glm::cross(fwd, c.up));
  const glm::vec3 up = glm::cross(right, fwd);
  const float th = std::tan(0.5f * c.vertical_fov);
  const glm::vec3 dir =
      glm::normalize(fwd + right * (probe.ndc.x * th * probe.aspect) - up * (probe.ndc.y * th));
  const data::HeightField& f = *t.heights;
  const float step = 0.5f * f.cell_size;
  for (float s = 0; s < c.far_plane; s += step) {
    const glm::vec3 p = c.position + s * dir;
    const glm::vec2 q = (glm::vec2(p) - glm::vec2(t.origin)) / f.cell_size;
    if (q.x < 0 || q.y < 0 || q.x > f.width - 1 || q.y > f.height - 1) continue;
    tx = static_cast<int>(std::lround(q.x));
    ty = static_cast<int>(std::lround(q.y));
    if (p.z <= t.origin.z + t.height_scale * f.at(tx, ty)) return true;
  }
  return false;
}

// The debug geometry, as components for the render extract: the light as a wire sphere, and
// the horizon wedges (and normal) of the texel under the probe as the terrain's DebugLines.
void terrain_debug_view(ecs::World& w) {
  w.query<const SphericalLight, DebugSphere>().each([&](const SphericalLight& l, DebugSphere& s) {
    const glm::vec3 c = l.radiance / std::max({l.radiance.x, l.radiance.y, l.radiance.z, 1e-6f});
    s = {l.position, l.radius, c * 4.0f};
  });
  const HorizonProbe* probe = w.try_resource<const HorizonProbe>();
  w.query<const Terrain, const TerrainHorizons, DebugLines>().each([&](const Terrain& terrain,
                                                                       const TerrainHorizons& h,
                                                                       DebugLines& out) {
    out.lines.clear();
    const Terrain* t = &terrain;
    if (!probe || !probe->enabled || !t->heights || !h.horizons || !h.normals) return;
    const terrain_shadow::HorizonGrid& g = *h.horizons;
    const data::HeightField& f = *t->heights;
    if (g.width != f.width || g.height != f.height || g.azimuths == 0) return;  // not yet swept
    int x, y;
    if (!pick_texel(w.resource<const Camera>(), *probe, *t, x, y)) return;
    const glm::vec3 p = t->origin +
                        glm::vec3(x * f.cell_size, y * f.cell_size, t->height_scale * f.at(x, y)) +
                        glm::vec3(0, 0, 5);
    const float len = 12.0f * t->heights->cell_size;
    glm::vec3 first{}, prev{};
    for (int k = 0; k < g.azimuths; ++k) {
      const float phi = 2 * std::numbers::pi_v<float> * k / g.azimuths, w_k = g.texel(x, y)[k];
      const glm::vec3 d(std::cos(phi) * std::cos(w_k), std::sin(phi) * std::cos(w_k),
                        std::sin(w_k));
      const glm::vec3 q = p + len * d;
      out.lines.push_back({p, q, {4.0f, 3.0f, 0.5f}});                // the horizon of azimuth k
      if (k > 0) out.lines.push_back({prev, q, {4.0f, 1.0f, 0.3f}});  // the wedge's rim
      if (k == 0) first = q;
      prev = q;
    }
    out.lines.push_back({prev, first, {4.0f, 1.0f, 0.3f}});
    out.lines.push_back(
        {p, p + len * (*h.normals)[static_cast<std::size_t>(y) * g.width + x], {0.5f, 2.0f, 4.0f}});
  });
}

}  // namespace

void populate_terrain_demo(ecs::World& world, const TerrainDemoConfig& config) {
  const std::filesystem::path dir = data_dir(config);
  const data::HeightField dem =
      assets::load_height_field(dir / "terrain" / "jacksboro_fault_dem.pgm");
  const int n = std::min({config.terrain_size, dem.width, dem.height});
  auto field = std::make_shared<data::HeightField>(
      data::crop(dem, (dem.width - n) / 2, (dem.height - n) / 2, n, n));
  auto map = std::make_shared<data::EnvironmentMap>(
      assets::load_environment_map(dir / "hdri" / config.environment));

  systems::emplace_render_resources(world);
  world.emplace_resource<Camera>();
  world.emplace_resource<FrameTime>();
  world.emplace_resource<HorizonProbe>();
  world.emplace_resource<DemoCameraMode>(DemoCameraMode{config.follow_pair});
  if (config.follow_pair) world.resource<HorizonProbe>().enabled = false;  // its fan hides them
  terrain_shadow::emplace_terrain_shadow_resources(world, config.shadow, config.light_refresh);
  auto& settings = world.resource<systems::RenderSettings>();
  settings.sky.environment = map;
  settings.view.exposure_ev = -0.5f;
  EnvironmentLight& env = world.emplace_resource<EnvironmentLight>();
  env.map = map;
  env.radiance = sh::project_equirect<sh::kDefaultBands>(map->rgb.data(), map->width, map->height);
  env.version = 1;
  // The map's sun (and any other bright source), found by environment.sources on the first
  // frame: the terrain shades it as a key light with its exact horizon, the rest of the map in
  // SH (issue 15; terrain_shadow_systems.h).
  if (config.environment_sources > 0) {
    environment::DetectionSettings detection;
    detection.source_count = config.environment_sources;
    environment::emplace_environment_resources(world, detection);
  }

  const float half = 0.5f * field->cell_size * (field->width - 1);
  // Vertical exaggeration 2: the DEM's 840 m of relief over 19 km reads better (a usual choice
  // for terrain views; the shadow system and the renderer both apply it).
  constexpr float kHeightScale = 2.0f;
  if (config.shape_ground) config.shape_ground(*field, {-half, -half, 0.0f}, kHeightScale);
  world.create_with(Terrain{field, {-half, -half, 0.0f}, {0.42f, 0.40f, 0.36f}, kHeightScale},
                    TerrainLighting{}, DebugLines{});
  blocker_accumulation::emplace_blocker_resources(world);
  spherical_lights::emplace_spherical_light_resources(world);
  populate_boulders(world, dir.string(), config.boulders);
  ProbeDemoConfig probes = config.probes;
  probes.sky_turns = config.sky_rotation_speed != 0;  // bake only the first step otherwise
  populate_probe_demo(world, dir.string(), map, probes);
  if (config.circling_light)
    world.create_with(SphericalLight{{0.0f, 0.0f, 1000.0f}, 350.0f, {50.0f, 36.0f, 18.0f}},
                      DebugSphere{});
}

void add_terrain_demo_systems(jobs::Schedule& s, const TerrainDemoConfig& config) {
  s.add_task("demo_clock", [](jobs::SystemContext& ctx) {
     FrameTime& t = ctx.world().resource<FrameTime>();
     t.dt = kFrameSeconds;
     t.elapsed += t.dt;
     ++t.frame;
   }).writes<FrameTime>();
  s.add_task("demo_animate", [config](jobs::SystemContext& ctx) { animate(ctx.world(), config); })
      .reads<FrameTime>()
      .writes<EnvironmentLight, SphericalLight, Terrain, systems::RenderSettings>();
  if (config.environment_sources > 0) environment::add_environment_systems(s);
  if (config.orbit_camera)
    s.add_task("demo_camera", [](jobs::SystemContext& ctx) { orbit(ctx.world()); })
        .reads<FrameTime, Terrain, DemoCameraMode, Boulder, components::Transform,
               components::Reflector>()
        .writes<Camera>();
  add_boulder_systems(s, config.circling_boulders);
  if (config.gameplay) config.gameplay(s);
  add_probe_demo_systems(s);
  terrain_shadow::add_terrain_shadow_systems(s);
  blocker_accumulation::add_blocker_systems(s);
  spherical_lights::add_spherical_light_systems(s);
  s.add_task("demo_debug_view", [](jobs::SystemContext& ctx) { terrain_debug_view(ctx.world()); })
      .reads<Camera, Terrain, TerrainHorizons, SphericalLight, HorizonProbe>()
      .writes<DebugSphere, DebugLines>();
  systems::add_render_extract(s);
}

}  // namespace penumbra::game
