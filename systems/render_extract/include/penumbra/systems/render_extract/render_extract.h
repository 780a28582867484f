// The render extract: the one system that reads ECS components for the renderer. Each frame it
// rebuilds the render::RenderPacket resource from
//   Camera (resource; defaults when absent)          -> packet.camera
//   RenderSettings (resource; defaults when absent)  -> packet.sky, packet.view
//   Terrain [+ TerrainLighting]                       -> packet.terrain (the first such entity;
//                                                       heights x height_scale)
//   Transform + MeshInstance [+ Material or BaseColor (albedo), VertexLighting] -> packet.meshes
//                                                     (Material::phong_exponent r > 0: a Blinn
//                                                     lobe of exponent 4r, reflectance 0.04)
//   DebugSphere, DebugLines, DebugPoints              -> packet.spheres, lines, points
//   EnvironmentLight (resource) when RenderSettings::environment.enabled
//                                                     -> packet.environment (below)
// Large arrays are shared by pointer (no copies); the packet's lists keep their capacity from
// frame to frame. It is the packet's only writer: whatever is to be drawn, debug geometry
// included, arrives as components (components/debug_shapes.h), the way Filament's
// FScene::prepare gathers renderables, so the systems that make it run before this one.
//
// The renderer then draws the packet after the frame's job graph has finished: it never reads
// ECS storage, and the packet holds no pointer into it.
//
// Threading: a task system (one thread); it only reads components.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "penumbra/data/height_field.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/render/packet.h"

namespace penumbra::systems {

// The renderer's per-pixel environment shading of the meshes (render::EnvironmentShading,
// [Ambrosj16] ch. 4; docs/environment.md "Renderer"), filled from the EnvironmentLight
// resource. Off by default: the packet's environment is then disabled and the meshes are drawn
// from their vertex lighting as before. On, the sources no wider than max_angular_radius get a
// shadow map (the first three, brightest first: components::key_light_mask), the other
// sources stay in every fragment's OEM; nothing is drawn differently until the environment
// stage has found sources for the current map (sources_version == version, all OEM sets).
struct EnvironmentShadingSettings {
  bool enabled = false;
  bool direct_diffuse = true;       // render::EnvironmentShading::direct_diffuse
  float max_angular_radius = 0.2f;  // radians, as the terrain's and blockers' key lights
  // Light switching ([Ambrosj16] sec. 5.2.1), per shadowed source: 0 off ... 1 on; a value in
  // between blends (ramp it over frames to fade a source in or out).
  std::array<float, render::EnvironmentShading::kMaxSources> weight{1.0f, 1.0f, 1.0f};
  std::uint32_t shadow_map_size = 1024;  // texels per side
};

// Resource: how to show the frame (sky, exposure, debug views), edited by the game and the
// ImGui overlay.
struct RenderSettings {
  render::Sky sky;
  render::ViewSettings view;
  EnvironmentShadingSettings environment;
};

// Adds the RenderPacket and RenderSettings resources when absent.
void emplace_render_resources(ecs::World& world);

// Registers the "render_extract" task system (reads and writes declared).
jobs::SystemBuilder add_render_extract(jobs::Schedule& schedule);

// A terrain's heights multiplied by its height_scale for the renderer (which draws heights as
// they are), remade only when the heights or the scale change. The system keeps one.
struct ScaledHeightsCache {
  std::shared_ptr<const data::HeightField> source;
  float scale = 1.0f;
  std::shared_ptr<const data::HeightField> scaled;
};

// What the system does, callable directly (tests, tools). Without a cache a scaled terrain is
// copied on every call.
void extract_render_packet(ecs::World& world, render::RenderPacket& packet,
                           ScaledHeightsCache* cache = nullptr);

}  // namespace penumbra::systems
