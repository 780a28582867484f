// The demo's rolling boulders (issue 11): the bunny and Suzanne (../shared/data/models; two
// bunnies for each Suzanne, whose 15k triangles cost lavapipe more), scaled to hill size, rolling
// over the terrain on circles. Each is a blocker (SphereSet: a fitted sphere set) and a receiver
// (its vertices), drawn as a mesh with the blocker system's VertexLighting: they shadow the terrain
// and each other, and the terrain shadows them.
//
// Sphere sets are fitted once (k-means, assets/sphere_fit.h) and kept as sphere files in
// `cache_dir` (checksummed; a corrupt or stale file is fitted again and rewritten).
//
// Systems: demo_boulders reads FrameTime, Terrain, Boulder; writes Transform (register before
// the blocker systems). demo_boulder_spheres reads Boulder, SphereSet, Transform, BoulderView;
// writes DebugLines: with BoulderView::spheres, three wire circles per sphere (the sets the
// blocker system sees), else nothing. Reflecting boulders carry a Reflector (sample points found
// on the simplified mesh at start, about 0.1 s per model) and a ReflectorRadiance.
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::game {

struct BoulderConfig {
  int count = 12;         // 0: none
  int spheres = 16;       // per model
  float radius = 250.0f;  // metres: the sphere set's bounding radius after scaling
  // Meshes drawn and shaded simplified to this deviation, relative to the model's extent (0: the
  // full meshes). 0.01: 0.4 pixels at the nearest the demo's camera comes (8 km, 20-pixel
  // boulders), with a tenth of the triangles at most (docs/blocker_accumulation.md).
  float simplify_error = 0.01f;
  std::string cache_dir;      // where fitted sphere files are kept; empty: fit every start
  bool show_spheres = false;  // the debug view: each sphere set as wire circles
  // The first `reflectors` boulders are also spherical lights (systems/spherical_lights,
  // [Guerrero08]): their spheres re-emit the light their surface reflects. With 2 or more, the
  // first is tinted bright red and the second, white, rolls beside it: the red one's light
  // bleeds onto the white one as they go.
  int reflectors = 2;
};

// Resource: what the boulders' debug view draws (BoulderConfig::show_spheres at start).
struct BoulderView {
  bool spheres = false;
};

// Per boulder: its path (a circle about the terrain's centre) and size.
struct Boulder {
  float path_radius = 0;         // metres
  float phase = 0;               // radians at t = 0
  float speed = 0;               // metres per second along the path (sign: direction)
  float radius = 0;              // bounding radius, metres (rests this high above the ground)
  float scale = 1;               // model units to metres
  glm::vec3 model_centre{0.0f};  // the sphere set's bounding centre, model units
  int model = 0;                 // 0: the bunny, 1: Suzanne
};

// Loads the models from `data_dir`/models, fits or loads their sphere sets, and adds `count`
// boulder entities. Throws assets::LoadError / FitError naming the file.
void populate_boulders(ecs::World& world, const std::string& data_dir, const BoulderConfig& config);
// roll: demo_boulders moves them on their circles; false: another system (the valley game's
// game_bodies) writes their Transforms.
void add_boulder_systems(jobs::Schedule& schedule, bool roll = true);

}  // namespace penumbra::game
