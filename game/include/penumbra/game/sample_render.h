// What the renderer shows of the sample world: a procedural terrain under the particle box,
// lit once on the CPU (sun + sky, no shadows: a stand-in until terrain_shadow lands), the
// particles as points coloured by their Irradiance, the point lights as small wire spheres, and
// a camera slowly orbiting the box.
//
// Systems (registered before systems::add_render_extract, which draws what they leave):
//   orbit_camera       writes Camera from FrameTime
//   extract_particles  reads Position + Irradiance, writes the DebugPoints of the scene's
//                      points entity (every k-th particle when there are more than max_points)
//   extract_lights     reads SampleLights, writes the scene's DebugSphere entities
#pragma once

#include <cstddef>

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::game {

struct SampleSceneConfig {
  int terrain_size = 256;      // height samples per side (1 m apart)
  float particle_gain = 4.0f;  // point colour = gain * irradiance
  // Points drawn at most (every k-th particle; 0: all). On lavapipe a point costs about
  // 0.2-0.3 us of setup and binning, so all 200,000 take ~50 ms a frame; 50,000 keep the
  // headless run near 30 fps while showing the same distribution.
  std::size_t max_points = 50'000;
};

// Adds the camera, render settings and packet resources, the terrain entity, and the debug
// entities (one DebugPoints, one DebugSphere per light of SampleLights: call after
// populate_sample_world).
void populate_sample_scene(ecs::World& world, const SampleSceneConfig& config = {});
// Registers the three systems, then render_extract; call after add_sample_systems.
void add_sample_render_systems(jobs::Schedule& schedule, const SampleSceneConfig& config = {});

}  // namespace penumbra::game
