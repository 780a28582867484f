// The blocker accumulation system in the job graph. Two task systems, in this order:
//
//   blockers.gather  reads SphereSet, Transform, BlockerSettingsResource, SphericalLight; writes
//       BlockerField
//       Every entity's spheres moved to world space (centre by the Transform, radius by its
//       largest axis scale) into one BlockerAccumulation and its spatial grid, one group per
//       entity (its set's bound: the hierarchy's object level, blocker_accumulation.h), and
//       the spherical lights, which receivers then see through the blockers. An entity
//       whose spheres or transform are not finite is left out and named in BlockerField::errors.
//   blockers.shade   reads Receiver, Transform, Material, Camera, BlockerField,
//       EnvironmentLight, Terrain; writes ReceiverLighting, VertexLighting. Per entity with a
//       Receiver, a Transform and a ReceiverLighting: its points and normals to world space,
//       then visibility, irradiance and outgoing radiance per point (tbb::parallel_for over
//       blocks of points), published as new shared arrays (and as VertexLighting, the radiance
//       per unit albedo, when the entity has one: what the renderer shows). A Material with a
//       Phong exponent shades glossy towards the Camera resource (one PhongLobe per exponent,
//       kept in BlockerField); with no camera, Lambertian. Receivers whose points are not finite
//       are named in BlockerField::errors and keep their previous lighting. With a Terrain in the
//       world, its cast shadow ([Giraud] sec. 4.1, log-SH wedges) joins the blockers' sum:
//       evaluated once per entity, at its Transform's origin (an object small against the terrain's
//       texels sees one horizon; per point it would cost ~10 us each).
//   blockers.terrain reads Terrain, TerrainHorizons, BlockerField, EnvironmentLight; writes
//       TerrainLighting, BlockerTerrainState (adds it to a terrain, structural)
//       The blockers' shadows on the terrain's texels (terrain_receivers.h): the terrain
//       system's lighting is kept as the base (BlockerTerrainState) and the shadowed copy
//       published in TerrainLighting; with no blocker in reach the base is published again.
//       Register after add_terrain_shadow_systems, so it runs after terrain_shadow.compose.
//
// The environment is optional (absent: black, visibility still computed); its SH is rotated by
// rotation_z. Entities with a SphereSet shadow their own receivers too (the plane rule of
// sphere_blocker.h keeps a surface point from being darkened by the sphere it sits in).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/terrain_shadow/log_wedge.h"

namespace penumbra::blocker_accumulation {

inline constexpr int kSystemBands = 4;  // = components::ReceiverLighting::kBands

enum class TerrainSampling { kEveryTexel, kEverySecondTexel };

// Resource: how the system shades.
struct BlockerSettingsResource {
  BlockerSettings settings;
  // Frames over which every reached terrain row is re-shaded once (1: all every frame).
  // Blockers that move a fraction of a texel per frame show no lag worth a whole frame's work.
  int refresh_period = 4;
  // Which terrain texels are shaded: all, or every second one along x and y (a quarter), the
  // others interpolated (terrain_receivers.h). Shadows of blockers several texels wide are
  // smooth at the SH's resolution (docs/blocker_accumulation.md gives the difference).
  TerrainSampling terrain_sampling = TerrainSampling::kEverySecondTexel;
  // Receiver points shaded per frame (0: all): entities are re-shaded whole, round robin, until
  // the budget is spent (at least one per frame; a new entity at once). The demo's 12 simplified
  // boulders hold 5,620 points: each is re-shaded every 5-6 frames (0.2 s, 7-10 degrees of
  // its roll).
  std::size_t receiver_budget = 1024;
  // The environment's sources (components/environment_light.h): kKeyLights shades each source
  // no wider than key_light_max_radius (radians) at the receivers as a key light, its disc
  // occluded by the blockers (BlockerAccumulation::key_light_visibility) and by the terrain's
  // horizon in its azimuth from the entity's origin (as its cast shadow), and the rest of the
  // map in SH ([Ambrosj16] ch. 4).
  // The blockers' shadows on the terrain keep the whole map's SH.
  components::EnvironmentSources sources = components::EnvironmentSources::kKeyLights;
  float key_light_max_radius = 0.2f;
};

// How blockers.gather groups a sphere set (cached per set array): the hierarchy's object level
// (blocker_accumulation.h). A set without parents is one group under its computed bound. A set
// whose spheres name parents ([Ren06] hierarchy, data::Sphere::parent) gives one group per root
// that has descendants: the root is the bound, its descendants without children of their own
// (the leaves) are the blockers; a root without children is a group of one. Parent indices out
// of range or in a cycle: the parents are ignored (flat set) and `error` says why.
struct SetLayout {
  struct Group {
    glm::vec3 centre{0.0f};  // the bound, in the set's frame
    float radius = 0;
    float coverage = 1;
    std::uint32_t first = 0, count = 0;  // leaves [first, first + count) of `leaves`
  };
  std::shared_ptr<const std::vector<components::Sphere>> keep;  // the set it describes
  std::vector<Group> groups;
  std::vector<std::uint32_t> leaves;  // indices into the set, group by group
  std::string error;
};

// Resource: this frame's world-space blockers, written by blockers.gather.
struct BlockerField {
  std::shared_ptr<BlockerAccumulation<kSystemBands>> accumulation;
  std::vector<std::string> errors;  // this frame's rejected inputs, each naming its entity
  std::size_t receivers = 0;        // receiver points shaded this frame
  std::uint64_t frame = 0;          // frames gathered (the refresh period's clock)
  std::uint64_t cursor = 0;         // next receiving entity of the round robin
  std::unordered_map<const void*, SetLayout> layouts;  // per SphereSet array
  // The terrain's log-SH wedges for the cast shadow on receivers (built on first use).
  std::shared_ptr<const terrain_shadow::LogWedge<kSystemBands>> cast_wedges;
  std::map<float, PhongLobe<kSystemBands>> lobes;  // per Material Phong exponent
};

// Per terrain entity: what blockers.terrain keeps between frames.
struct BlockerTerrainState {
  std::shared_ptr<const std::vector<glm::vec3>> base;       // the terrain system's lighting
  std::shared_ptr<const std::vector<glm::vec3>> published;  // ours, with the blockers' shadows
  std::shared_ptr<const terrain_shadow::LogWedge<kSystemBands>> wedges;
  std::size_t reached = 0;       // texels within some blocker's reach, in the rows last re-shaded
  std::vector<glm::vec3> ratio;  // per texel: the blockers' shadow (1: none), terrain_receivers.h
};

// Adds BlockerSettingsResource (with `settings`) and BlockerField when absent.
void emplace_blocker_resources(ecs::World& world, const BlockerSettings& settings = {});
void add_blocker_systems(jobs::Schedule& schedule);

}  // namespace penumbra::blocker_accumulation
