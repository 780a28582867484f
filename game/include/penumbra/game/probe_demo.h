// The probe cloud in the main job (issue 12, "In the main job"): a cloud of irradiance probes
// over the demo's terrain and a few floating objects lit by it through the probe-cloud traversal
// system ([Sukys14] sec. 3.2, [Cupisz12]; systems/probe_cloud probe_systems.h), with debug views.
//
// The cloud: grid x grid probes over the terrain at each of `heights` above the local ground,
// tetrahedralized at start-up (build_probe_cloud). Their irradiance SH (3 bands) are baked by the
// probe bake's capture (probe_sky_bake.h: reference::radiance_sh through the terrain, with one
// diffuse bounce off its albedo, `samples` per probe) once per sky step (2 pi / sky_steps), and
// cached in `cache_dir` (penumbra_play: OUT/probes, default build/play/probes), so only the
// first run with given inputs traces rays. When the sky's rotation reaches another step the
// resource's cloud is replaced by that step's (no rays): the walk's cached cells are then
// invalidated and every object locates afresh once. Terrain edits do not re-bake (the probes
// keep the start-up terrain's lighting); the spherical light does not reach the probes.
//
// Systems (add_probe_demo_systems, in this order):
//   demo_probe_floaters  reads FrameTime, Terrain, ProbeFloater; writes Transform
//                        (each object along its circle, hovering over the ground, turned along
//                        its motion)
//   demo_probe_sky       reads EnvironmentLight; writes ProbeSkyBake, ProbeCloudResource
//                        (re-projects the probes' SH when the sky turned by a cell)
//   probes.prepare, probes.walk   (systems/probe_cloud probe_systems.h)
//   demo_probe_shade     reads ProbeLighting, Transform, ProbeShadedMesh; writes VertexLighting
//                        (E(n) / pi per vertex normal: the radiance per unit albedo the renderer
//                        shows, as blockers.shade writes for the boulders)
//   demo_probe_debug     reads ProbeDebugView, ProbeWalkState, ProbeAnchor, ProbeCloudView;
//                        writes DebugLines, ProbeWalkTrace (the probes as wire spheres, each
//                        object's cell and last walk, when ProbeDebugView is on; else nothing)
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/components/terrain.h"
#include "penumbra/data/environment_map.h"
#include "penumbra/ecs/world.h"
#include "penumbra/game/probe_sky_bake.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::game {

struct ProbeDemoConfig {
  int count = 5;  // floating objects (bunny, Suzanne, ...); 0: no objects and no cloud
  int grid = 12;  // probes per side over the terrain (>= 2)
  std::vector<float> heights{120.0f, 450.0f, 1200.0f};  // metres above the local ground
  int sky_steps = 32;            // sky rotations baked, 2 pi / sky_steps apart
  int samples = 128;             // capture samples per probe and step
  bool bounce = true;            // one diffuse bounce off the terrain
  bool sky_turns = true;         // bake every step at start-up (false: step 0, others when reached)
  std::string cache_dir;         // where baked steps are kept ("": nowhere, baked at every start)
  float radius = 180.0f;         // metres: the objects' bounding radius
  float hover = 260.0f;          // metres: the objects' centre above the highest ground under them
  float simplify_error = 0.02f;  // the meshes simplified as the boulders' (boulders.h)
  bool show = false;             // ProbeDebugView at start
  // More probes, e.g. along a canyon's floor, from the terrain as populated: (x, y) as fractions
  // of the terrain's width from its centre, z the height above the ground there in metres.
  std::function<std::vector<glm::vec3>(const components::Terrain&)> extra_probes;
  // Static meshes for the bake (occluders and reflectors), from the terrain as populated.
  std::function<std::vector<BakeMesh>(const components::Terrain&)> bake_meshes;
};

// Resource: the probe debug views (penumbra_play --probes-debug, key P in the window).
struct ProbeDebugView {
  bool enabled = false;
  float probe_radius = 90.0f;  // metres: the probes' wire spheres
};

// Per floating object: its path (a circle about the terrain's centre) and size.
struct ProbeFloater {
  float path_radius = 0;  // metres
  float phase = 0;        // radians at t = 0
  float speed = 0;        // metres per second along the path (sign: direction)
  float hover = 0;        // metres above the ground
  float radius = 0;       // metres: bounding radius
  float scale = 1;        // model units to metres
  glm::vec3 model_centre{0.0f};
};

// Per probe-shaded mesh: its vertex normals (object space, one per MeshInstance position).
struct ProbeShadedMesh {
  std::shared_ptr<const std::vector<glm::vec3>> normals;
};

// Per object (debug): the cell its anchor held before this frame's walk, to draw the walk.
struct ProbeWalkTrace {
  std::int32_t cell = -1;
  std::uint64_t generation = 0;
};

// Marks the entity whose DebugLines draw the probes.
struct ProbeCloudView {};

// Resource: the baked steps and the bake's figures, for re-placing the SH when the sky turns.
struct ProbeSkyBake {
  struct Data;
  std::shared_ptr<Data> data;
  int shift = 0;                   // sky steps the current SH are turned by
  std::uint64_t bakes = 0;         // clouds published so far (the start-up one included)
  double startup_seconds = 0;      // the start-up build: bake or cache, tetrahedralization
  double bake_seconds = 0;         // of which the steps (traced or loaded)
  double last_bake_ms = 0;         // the last replacement
  std::size_t steps_baked = 0;     // steps traced (this run)
  std::size_t steps_loaded = 0;    // steps read from the cache
  std::string cache_folder;        // "" without a cache
  std::vector<std::string> notes;  // cache files rebaked and why
};

// Builds the cloud over the world's Terrain under `map` (rotation 0) and adds the resources
// (probe_systems.h's, ProbeDebugView, ProbeSkyBake) and the objects (models from
// data_dir/models). Call after the Terrain entity exists. count == 0: only ProbeDebugView.
void populate_probe_demo(ecs::World& world, const std::string& data_dir,
                         std::shared_ptr<const data::EnvironmentMap> map,
                         const ProbeDemoConfig& config);
void add_probe_demo_systems(jobs::Schedule& schedule);

}  // namespace penumbra::game
