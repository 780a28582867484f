// The demo scene of the main job: the real elevation model (../shared/data/terrain) lit by the
// terrain shadow system under an HDR sky whose SH rotates slowly, a spherical light circling
// over it, and a brush edit (crater or raise, alternating) every few seconds, so soft shadows
// visibly follow. A debug view draws the horizon wedges of one texel (the one under the cursor
// in the window, the view centre headless).
//
// Systems (registered by add_terrain_demo_systems in this order; the job graph runs those
// whose declared accesses do not conflict side by side):
//   demo_clock        writes FrameTime (fixed 1/30 s steps: headless runs are reproducible)
//   demo_animate      reads FrameTime, writes EnvironmentLight (rotation), SphericalLight
//                     (path), Terrain (brush edits), RenderSettings (sky rotation)
//   environment.sources (systems/environment: the map's sun found on the first frame, when
//                     environment_sources > 0; the terrain and the boulders take it as a key light)
//   demo_camera       reads FrameTime, Terrain, writes Camera (slow orbit; not with orbit_camera
//                     off: the valley game's camera takes its place)
//   (gameplay)        TerrainDemoConfig::gameplay's systems (valley_game.h), when set
//   demo_boulders     reads FrameTime, Terrain, Boulder, writes Transform (boulders.h)
//   demo_probe_floaters, demo_probe_sky, probes.prepare, probes.walk, demo_probe_shade,
//   demo_probe_debug  (probe_demo.h: floating objects lit by the probe cloud over the terrain,
//                     systems/probe_cloud's traversal, and its debug views)
//   terrain_shadow.*  (systems/terrain_shadow)
//   blockers.*        (systems/blocker_accumulation: the boulders' shadows, after the terrain's)
//   spherical_lights.* (systems/spherical_lights: the reflecting boulders' one-bounce light on
//                     the boulders, after the blockers'; key I toggles it in a window)
//   demo_debug_view   reads Camera, Terrain, TerrainHorizons, SphericalLight, HorizonProbe,
//                     writes DebugSphere (the light's extent) and the terrain's DebugLines (the
//                     horizon wedges under the probe)
//   render_extract    (systems/render_extract: the packet's only writer)
#pragma once

#include <functional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"

#include "penumbra/ecs/world.h"
#include "penumbra/game/boulders.h"
#include "penumbra/game/probe_demo.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/terrain_shadow/light_refresh.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::game {

// The simulation's fixed step (demo_clock's FrameTime::dt): headless runs are reproducible.
inline constexpr float kDemoStepSeconds = 1.0f / 30.0f;

struct TerrainDemoConfig {
  std::string data_dir;                     // ../shared/data; empty: PENUMBRA_SHARED_DATA
  std::string environment = "sunrise.exr";  // in data_dir/hdri: a low sun, so shadows are long
  // Bright sources to find in the map (systems/environment) and shade as the terrain's key
  // lights; 0: the map as SH alone.
  int environment_sources = 1;
  int terrain_size = 257;  // samples per side, cropped from the DEM's centre (2^k + 1: the
                           // renderer's terrain_bintree.h splits no border)
  float sky_rotation_speed = 0.05f;  // rad/s
  float edit_interval = 3.0f;        // seconds between brush edits; <= 0: none
  terrain_shadow::TerrainShadowConfig shadow{};
  terrain_shadow::LightRefreshConfig light_refresh{};  // light re-shading per tile and frame
  BoulderConfig boulders{};                            // rolling blockers (boulders.h)
  ProbeDemoConfig probes{};       // the probe cloud and the objects it lights (probe_demo.h)
  bool follow_pair = false;       // start with the camera on the red-and-white boulder pair
  bool circling_light = true;     // the demo's spherical light circling over the valley
  bool orbit_camera = true;       // demo_camera; false: another system writes Camera
  bool circling_boulders = true;  // demo_boulders; false: another system moves the boulders
  // Systems of a game played in this world (valley_game.h), scheduled after the demo's clock,
  // animation and boulders and before the lighting, so the lights shade this step's moves.
  std::function<void(jobs::Schedule&)> gameplay;
  // Reshapes the cropped heights before anything sees them (the valley game's canyon):
  // f(heights in field units, world origin of sample (0, 0), height scale).
  std::function<void(data::HeightField&, glm::vec3, float)> shape_ground;
};

// Resource: what the demo's camera does: orbit the whole terrain, or follow the colour-bleeding
// boulder pair (boulders.h) from 2.5 km, outside its circle (key C toggles it in a window).
struct DemoCameraMode {
  bool follow_pair = false;
};

// Resource: which texel's horizon the debug view draws, as a point on the screen in NDC
// ([-1, 1]^2, y down); the demo's camera ray through it picks the terrain.
struct HorizonProbe {
  bool enabled = true;
  glm::vec2 ndc{0.0f, 0.0f};
  float aspect = 16.0f / 9.0f;  // of the view, to build the ray
};

// Loads the DEM and the map (throws assets::LoadError / std::invalid_argument naming the file)
// and adds the entities and resources.
void populate_terrain_demo(ecs::World& world, const TerrainDemoConfig& config = {});
void add_terrain_demo_systems(jobs::Schedule& schedule, const TerrainDemoConfig& config = {});

}  // namespace penumbra::game
