// The sample world: particles that move, bounce, swirl around their centroid, die and respawn,
// lit by a few point lights. It exercises every scheduler feature (parallel chunk systems,
// resources, a deterministic reduction, deferred structural changes) until the lighting
// systems and the demo game replace it as the main job.
#pragma once

#include <cstddef>
#include <cstdint>

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::game {

struct SampleWorldConfig {
  std::size_t particles = 200'000;
  std::size_t lights = 8;
  std::uint32_t seed = 1;
};

// Plain data of the sample world (components and resources).
struct Irradiance {
  float r = 0, g = 0, b = 0;
};
struct PointLight {
  float x, y, z;
  float r, g, b;
};
struct SampleLights {
  PointLight lights[16];
  std::size_t count = 0;
};
struct Centroid {
  float x = 0, y = 0, z = 0;
  std::size_t count = 0;
};

// Creates the particles and resources (FrameTime, SampleLights, Centroid).
void populate_sample_world(ecs::World& world, const SampleWorldConfig& config);
// Registers the sample systems: clock, integrate, bounce, age (spawns), centroid (reduction),
// swirl, move_lights, light.
void add_sample_systems(jobs::Schedule& schedule);

}  // namespace penumbra::game
