// The valley game's canyon: a straight gorge cut into the elevation model across the floating
// objects' paths, spanned by rock arches, with probes along its floor. Entering it, the
// probe-lit objects darken (the baked cloud sees the walls close the sky) and the arches' soft
// shadows fall across the floor (the blocker system: each arch is a static sphere set).
//
// carve_canyon runs on the cropped heights before anything else sees them
// (TerrainDemoConfig::shape_ground); canyon_probes gives ProbeDemoConfig::extra_probes;
// add_canyon_arches adds the arch entities once the terrain exists.
// Threading: pure functions, apart from add_canyon_arches (the world, one thread).
#pragma once

#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/components/terrain.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/data/sphere_set.h"
#include "penumbra/ecs/world.h"

namespace penumbra::game {

struct CanyonConfig {
  // The gorge's axis, as fractions of the field's width from its centre (both ends).
  glm::vec2 from{-0.42f, -0.16f}, to{0.42f, 0.02f};
  float depth = 450.0f;          // world metres below the land around it
  float half_width = 420.0f;     // metres: full depth within it, back to the land at twice it
  int arches = 3;                // spanning the gorge, evenly along it (not at its ends)
  float arch_radius = 540.0f;    // metres: the arch's centre line, a half circle over the floor
  float arch_thickness = 95.0f;  // metres: the rock's radius about that line
  glm::vec3 arch_albedo{0.58f, 0.34f, 0.22f};       // sandstone
  std::vector<float> probe_heights{90.0f, 300.0f};  // above the floor, every probe_spacing
  float probe_spacing = 700.0f;
};

// Lowers `heights` (samples in field units, world height = height_scale x value) along the
// axis: world depth `depth` within half_width, smoothly back to 0 at twice it. `origin` is the
// world position of sample (0, 0).
void carve_canyon(data::HeightField& heights, glm::vec3 origin, float height_scale,
                  const CanyonConfig& config);

// World xy of the axis' ends for a field of `width` metres centred at `centre`.
void canyon_axis(glm::vec2 centre, float width, const CanyonConfig& config, glm::vec2& a,
                 glm::vec2& b);

// Probes along the floor for ProbeDemoConfig::extra_probes: (x, y) as fractions of the field's
// width from its centre, z the height above the ground; every probe_spacing metres of a field
// `width` metres wide.
std::vector<glm::vec3> canyon_probes(float width, const CanyonConfig& config);

// An arch: a tube of `thickness` about a half circle of `radius` standing on `base` (world),
// spanning across `axis` (unit, horizontal): its mesh (world frame) and its sphere set.
struct ArchShape {
  std::shared_ptr<data::MeshData> mesh;
  std::shared_ptr<std::vector<data::Sphere>> spheres;
};
ArchShape make_arch(glm::vec3 base, glm::vec2 axis, float radius, float thickness);

// The arches over the carved canyon of `terrain` (world frame), evenly along its axis.
std::vector<ArchShape> canyon_arches(const components::Terrain& terrain,
                                     const CanyonConfig& config);

// Adds the arches over the carved canyon of the world's terrain: static blockers and receivers
// (SphereSet, Receiver, ReceiverLighting, VertexLighting), drawn as meshes.
void add_canyon_arches(ecs::World& world, const CanyonConfig& config);

}  // namespace penumbra::game
