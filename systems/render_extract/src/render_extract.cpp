#include "penumbra/systems/render_extract/render_extract.h"

#include <numbers>

#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"

namespace penumbra::systems {
namespace {
using components::BaseColor;
using components::Camera;
using components::DebugLine;
using components::DebugLines;
using components::DebugPoint;
using components::DebugPoints;
using components::DebugSphere;
using components::EnvironmentLight;
using components::Material;
using components::MeshInstance;
using components::ReceiverLighting;
using components::Terrain;
using components::TerrainLighting;
using components::Transform;
using components::VertexLighting;

render::CameraView to_render(const Camera& c) {
  return {c.position, c.target, c.up, c.vertical_fov, c.near_plane, c.far_plane};
}
}  // namespace

void emplace_render_resources(ecs::World& world) {
  if (world.try_resource<render::RenderPacket>() == nullptr)
    world.emplace_resource<render::RenderPacket>();
  if (world.try_resource<RenderSettings>() == nullptr) world.emplace_resource<RenderSettings>();
}

namespace {
std::shared_ptr<const data::HeightField> scaled_heights(const Terrain& t,
                                                        ScaledHeightsCache* cache) {
  if (t.height_scale == 1.0f || !t.heights) return t.heights;
  if (cache && cache->source == t.heights && cache->scale == t.height_scale) return cache->scaled;
  auto f = std::make_shared<data::HeightField>(*t.heights);
  for (float& h : f->heights) h *= t.height_scale;
  if (cache) *cache = {t.heights, t.height_scale, f};
  return f;
}

// packet.environment from the EnvironmentLight resource (RenderSettings::environment); the OEM
// sets are re-packed only when the environment's version changes.
void extract_environment(const ecs::World& world, const EnvironmentShadingSettings& settings,
                         render::EnvironmentShading& out) {
  out.enabled = settings.enabled;
  out.sources.clear();
  out.direct_diffuse = settings.direct_diffuse;
  out.shadow_map_size = settings.shadow_map_size;
  const EnvironmentLight* env =
      settings.enabled ? world.try_resource<const EnvironmentLight>() : nullptr;
  if (env == nullptr) return;
  const std::size_t keys = components::key_light_mask(*env, settings.max_angular_radius);
  const std::size_t n = env->sources.size();
  if (keys == 0 || env->oem_sh3.size() != (std::size_t{1} << n)) return;
  std::uint32_t shadowed = 0;
  for (std::size_t j = 0; j < n && out.sources.size() < render::EnvironmentShading::kMaxSources;
       ++j) {
    if (!(keys >> j & 1)) continue;
    const auto& s = env->sources[j];
    out.sources.push_back({components::world_direction(s, env->rotation_z),
                           env->intensity * s.irradiance, static_cast<std::uint32_t>(j),
                           settings.weight[out.sources.size()]});
    shadowed |= 1u << j;
  }
  out.present_mask = ((1u << n) - 1) & ~shadowed;
  out.rotation_z = env->rotation_z;
  if (!out.oem_sh || out.version != env->version || out.oem_source_count != n) {
    auto sets = std::make_shared<std::vector<float>>();
    sets->reserve(env->oem_sh3.size() * 27);
    for (const auto& set : env->oem_sh3)
      for (const auto& channel : set) sets->insert(sets->end(), channel.begin(), channel.end());
    out.oem_sh = std::move(sets);
    out.oem_source_count = static_cast<std::uint32_t>(n);
    out.version = env->version;
  }
}
}  // namespace

void extract_render_packet(ecs::World& world, render::RenderPacket& packet,
                           ScaledHeightsCache* cache) {
  packet.clear_lists();
  const Camera* camera = world.try_resource<const Camera>();
  packet.camera = to_render(camera ? *camera : Camera{});
  const RenderSettings* settings = world.try_resource<const RenderSettings>();
  if (settings) {
    packet.sky = settings->sky;
    packet.view = settings->view;
  }
  extract_environment(world, settings ? settings->environment : EnvironmentShadingSettings{},
                      packet.environment);

  packet.terrain = {};
  bool have_terrain = false;
  world.query<const Terrain>().each([&](ecs::Entity e, const Terrain& t) {
    if (have_terrain) return;
    have_terrain = true;
    packet.terrain.heights = scaled_heights(t, cache);
    packet.terrain.origin = t.origin;
    packet.terrain.albedo = t.albedo;
    if (const TerrainLighting* l = world.get<TerrainLighting>(e)) {
      packet.terrain.lighting = l->rgb;
      packet.terrain.lighting_width = l->width;
      packet.terrain.lighting_height = l->height;
    }
  });

  world.query<const Transform, const MeshInstance>().each(
      [&](ecs::Entity e, const Transform& t, const MeshInstance& m) {
        if (!m.mesh) return;
        render::MeshDraw d;
        d.mesh = m.mesh;
        d.transform = t.world;
        const BaseColor* c = world.get<BaseColor>(e);
        const Material* mat = world.get<Material>(e);
        d.albedo = mat ? mat->albedo : c ? glm::vec3(c->rgba) : glm::vec3(m.mesh->base_color);
        if (mat && mat->phong_exponent > 0) d.specular_exponent = 4.0f * mat->phong_exponent;
        if (const VertexLighting* l = world.get<VertexLighting>(e)) d.vertex_lighting = l->rgb;
        // One-bounce light from spherical lights ([Guerrero08] eq. 12) and the local lights'
        // direct light when spherical_lights.gather gives it (LocalLightRouting), each its own term
        // in ReceiverLighting: added here as radiance per unit albedo, E / pi.
        const ReceiverLighting* r = world.get<ReceiverLighting>(e);
        for (const auto* term : {r ? &r->indirect : nullptr, r ? &r->local : nullptr}) {
          if (!term || !*term || !d.vertex_lighting || (*term)->size() != d.vertex_lighting->size())
            continue;
          auto sum = std::make_shared<std::vector<glm::vec3>>(*d.vertex_lighting);
          for (std::size_t i = 0; i < sum->size(); ++i)
            (*sum)[i] += (**term)[i] * std::numbers::inv_pi_v<float>;
          d.vertex_lighting = std::move(sum);
        }
        packet.meshes.push_back(std::move(d));
      });

  world.query<const DebugSphere>().each([&](const DebugSphere& s) {
    packet.spheres.push_back({s.center, s.radius, s.color});
  });
  world.query<const DebugLines>().each([&](const DebugLines& d) {
    for (const DebugLine& l : d.lines) packet.lines.push_back({l.a, l.b, l.color});
  });
  world.query<const DebugPoints>().each([&](const DebugPoints& d) {
    for (const DebugPoint& p : d.points) packet.points.push_back({p.position, p.color});
  });
}

jobs::SystemBuilder add_render_extract(jobs::Schedule& schedule) {
  return schedule
      .add_task("render_extract",
                [cache = std::make_shared<ScaledHeightsCache>()](jobs::SystemContext& ctx) {
                  ecs::World& w = ctx.world();
                  extract_render_packet(w, w.resource<render::RenderPacket>(), cache.get());
                })
      .reads<Camera, RenderSettings, Terrain, TerrainLighting, Transform, MeshInstance, BaseColor,
             Material, VertexLighting, ReceiverLighting, DebugSphere, DebugLines, DebugPoints,
             EnvironmentLight>()
      .writes<render::RenderPacket>();
}

}  // namespace penumbra::systems
