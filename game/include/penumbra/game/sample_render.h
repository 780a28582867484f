// What the renderer shows of the sample world: a procedural terrain under the particle box,
// lit once on the CPU (sun + sky, no shadows: a stand-in until terrain_shadow lands), the
// particles as points coloured by their Irradiance, the point lights as small wire spheres, and
// a camera slowly orbiting the box.
//
// Systems (registered after systems::add_render_extract, so they append to its packet):
//   orbit_camera       writes Camera from FrameTime
//   extract_particles  reads Position + Irradiance, appends packet points (every k-th particle
//                      when there are more than max_points)
//   extract_lights     reads SampleLights, appends packet spheres
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

// Adds the camera, render settings and packet resources and the terrain entity.
void populate_sample_scene(ecs::World& world, const SampleSceneConfig& config = {});
// Registers orbit_camera before the extract and the two packet writers; call after
// add_sample_systems. Registers render_extract itself.
void add_sample_render_systems(jobs::Schedule& schedule, const SampleSceneConfig& config = {});

}  // namespace penumbra::game
