#include "penumbra/systems/spherical_lights/spherical_light_systems.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/frame_work.h"
#include "common/stability.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/reflector.h"
#include "penumbra/components/reflector_radiance.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"
#include "test_meshes.h"

namespace penumbra::spherical_lights {
namespace {

using components::Receiver;
using components::ReceiverLighting;
using components::Transform;

// A red 2 m cube (one sphere) standing 3 m beside a column of receivers facing it, on a ground
// of receivers facing up, under a uniform white sky.
struct Scene {
  ecs::World world;
  ecs::Entity wall, cube;
  jobs::Schedule schedule;
  jobs::Executor executor{2};
  Scene() {
    blocker_accumulation::emplace_blocker_resources(world);
    emplace_spherical_light_resources(world);
    auto& env = world.emplace_resource<components::EnvironmentLight>();
    env.radiance[0][0] = env.radiance[1][0] = env.radiance[2][0] =
        std::sqrt(4 * std::numbers::pi_v<float>);
    auto points = std::make_shared<std::vector<glm::vec3>>();
    for (int z = 0; z < 5; ++z) points->push_back({0.0f, 0.0f, 0.5f * static_cast<float>(z)});
    auto normals = std::make_shared<std::vector<glm::vec3>>(points->size(), glm::vec3(1, 0, 0));
    wall = world.create_with(Receiver{points, normals}, Transform{}, ReceiverLighting{});
    const data::MeshData box =
        test::box_mesh(glm::vec3(-1), glm::vec3(1), glm::vec3(0.9f, 0.1f, 0.1f));
    auto spheres = std::make_shared<std::vector<components::Sphere>>(
        std::vector<components::Sphere>{{glm::vec3(0), std::sqrt(3.0f) + 1e-3f, -1}});
    auto samples = std::make_shared<const data::ReflectorSamples>(sample_reflector(box, *spheres));
    cube = world.create_with(components::SphereSet{spheres},
                             Transform{glm::translate(glm::mat4(1), {4, 0, 1})},
                             components::Reflector{samples}, components::ReflectorRadiance{});
    blocker_accumulation::add_blocker_systems(schedule);
    add_spherical_light_systems(schedule);
  }
  const ReceiverLighting& wall_lighting() { return *world.get<ReceiverLighting>(wall); }
};

TEST(SphericalLightSystems, ARedCubeBleedsRedOntoTheWallFacingIt) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  const ReceiverLighting& l = s.wall_lighting();
  ASSERT_NE(l.indirect, nullptr);
  ASSERT_EQ(l.indirect->size(), 5u);
  const glm::vec3 e = (*l.indirect)[2];  // 1 m up, level with the cube's centre
  EXPECT_GT(e.x, 0.05f);
  EXPECT_GT(e.x, 5 * e.y);  // red
  EXPECT_NEAR(e.y, e.z, 1e-4f);
  EXPECT_NE(s.world.get<components::ReflectorRadiance>(s.cube)->radiance, nullptr);
  EXPECT_EQ(s.world.resource<SphericalLightField>().lights, 1u);
  EXPECT_GT(s.world.resource<SphericalLightField>().sample_points, 80u);
  // Moving the cube away: less light.
  s.world.get_mut<Transform>(s.cube)->world = glm::translate(glm::mat4(1), {8, 0, 1});
  s.executor.run(s.schedule, s.world);
  EXPECT_LT((*s.wall_lighting().indirect)[2].x, 0.5f * e.x);
}

// EnvironmentLight::intensity (the valley game's dusk) scales what the cube reflects: the bounce
// is linear in the sky. It arrives when the reflector's turn comes (reflect_period frames).
TEST(SphericalLightSystems, TheSkysIntensityScalesTheBounce) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  const glm::vec3 full = (*s.wall_lighting().indirect)[2];
  s.world.resource<components::EnvironmentLight>().intensity = 0.25f;
  const int period = s.world.resource<const SphericalLightSettingsResource>().reflect_period;
  for (int f = 0; f < period + 1; ++f) s.executor.run(s.schedule, s.world);
  const glm::vec3 dimmed = (*s.wall_lighting().indirect)[2];
  EXPECT_GT(full.x, 0.05f);
  EXPECT_NEAR(dimmed.x, 0.25f * full.x, 1e-3f * full.x);
  EXPECT_NEAR(dimmed.y, 0.25f * full.y, 1e-3f * full.x);
}

TEST(SphericalLightSystems, ReflectorsTakeTurnsAndFarReceiversSkipTheGather) {
  Scene s;
  auto far_point = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(1000, 0, 0));
  auto far_normal = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(-1, 0, 0));
  const ecs::Entity far =
      s.world.create_with(Receiver{far_point, far_normal}, Transform{}, ReceiverLighting{});
  std::vector<std::size_t> lit;
  for (int i = 0; i < 8; ++i) {
    s.executor.run(s.schedule, s.world);
    lit.push_back(s.world.resource<SphericalLightField>().sample_points);
  }
  // reflect_period 4: the one reflector's points are lit on its first frame, then once every 4
  // frames: 2 or 3 updates in 8 frames (the phase depends on its entity index), never two in a row
  // after the first.
  int updates = 0;
  for (std::size_t i = 0; i < lit.size(); ++i) {
    updates += lit[i] > 0 ? 1 : 0;
    if (i >= 2) {
      EXPECT_FALSE(lit[i] > 0 && lit[i - 1] > 0) << i;
    }
  }
  EXPECT_GE(updates, 2);
  EXPECT_LE(updates, 3);
  EXPECT_GT(lit[0], 0u);
  EXPECT_EQ(s.world.resource<SphericalLightField>().lights, 1u);  // placed every frame
  const auto& indirect = *s.world.get<ReceiverLighting>(far)->indirect;
  ASSERT_EQ(indirect.size(), 1u);
  EXPECT_EQ(indirect[0], glm::vec3(0.0f));
}

// The frame table's work report (jobs::report_work): spherical_lights.reflect relights a
// reflector on its turn (reflect_period) and reports the others skipped; gather shades new
// receivers at once, then within its point budget.
TEST(SphericalLightSystems, ReportsTheWorkItSkipsPerFrame) {
  Scene s;
  auto step = [&](std::string_view name) {
    return penumbra::test::system_timing(s.executor.last_frame(), name);
  };
  s.executor.run(s.schedule, s.world);
  EXPECT_TRUE(step("spherical_lights.reflect").reported);
  EXPECT_EQ(step("spherical_lights.reflect").done, 1u) << "a new reflector is lit at once";
  EXPECT_EQ(step("spherical_lights.gather").done, 1u);
  EXPECT_EQ(step("spherical_lights.gather").skipped, 0u);
  int done = 0, skipped = 0;
  for (int i = 0; i < 8; ++i) {
    s.executor.run(s.schedule, s.world);
    const bool lit = s.world.resource<SphericalLightField>().sample_points > 0;  // this frame
    EXPECT_EQ(step("spherical_lights.reflect").done, lit ? 1u : 0u) << i;
    EXPECT_EQ(step("spherical_lights.reflect").skipped, lit ? 0u : 1u) << i;
    done += static_cast<int>(step("spherical_lights.reflect").done);
    skipped += static_cast<int>(step("spherical_lights.reflect").skipped);
  }
  EXPECT_EQ(done, 2) << "once every 4 frames";
  EXPECT_EQ(skipped, 6);
}

TEST(SphericalLightSystems, SwitchedOffClearsTheIndirectTerm) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  ASSERT_NE(s.wall_lighting().indirect, nullptr);
  s.world.resource<SphericalLightSettingsResource>().indirect = false;
  s.executor.run(s.schedule, s.world);
  EXPECT_EQ(s.wall_lighting().indirect, nullptr);
  EXPECT_NE(s.wall_lighting().irradiance, nullptr);  // the direct light stays
}

TEST(SphericalLightSystems, ABadTransformIsNamedAndEmitsNothing) {
  PENUMBRA_STABILITY("a non-finite or zero-scale transform in the ECS",
                     "named in SphericalLightField::errors; the object emits nothing", "-");
  Scene s;
  s.world.get_mut<Transform>(s.cube)->world[3][0] = NAN;
  s.executor.run(s.schedule, s.world);
  const SphericalLightField& field = s.world.resource<SphericalLightField>();
  EXPECT_EQ(field.lights, 0u);
  bool named = false;
  for (const std::string& e : field.errors) {
    named = named || e.find("entity " + std::to_string(s.cube.index)) != std::string::npos;
  }
  EXPECT_TRUE(named);
  EXPECT_EQ((*s.wall_lighting().indirect)[2], glm::vec3(0.0f));
}

TEST(SphericalLightSystems, AnObjectSunkIntoTheTerrainEmitsNothing) {
  PENUMBRA_STABILITY("an object sunk into the terrain",
                     "sample points under the surface reflect nothing: it emits nothing", "-");
  // A flat terrain 5 m up, over the whole cube: every sample point is under its surface and
  // reflects nothing, so the cube's light is black. (The cast shadow alone would leave the
  // log-SH floor, eps = 0.2 of the sky: 0.18 of the albedo measured before this rule.)
  Scene s;
  auto field = std::make_shared<data::HeightField>();
  field->width = field->height = 33;
  field->cell_size = 1.0f;
  field->heights.assign(33 * 33, 5.0f);
  s.world.create_with(components::Terrain{field, {-16.0f, -16.0f, 0.0f}});
  s.executor.run(s.schedule, s.world);
  const auto& radiance = *s.world.get<components::ReflectorRadiance>(s.cube)->radiance;
  EXPECT_LT(std::abs(radiance[0][0][0]), 0.02f * std::sqrt(4 * std::numbers::pi_v<float>));
  EXPECT_LT((*s.wall_lighting().indirect)[2].x, 0.005f);
  EXPECT_TRUE(std::isfinite((*s.wall_lighting().indirect)[2].x));
}

// With the terrain and blocker systems: a red cube standing on flat ground tints the texels
// around it red, on top of the blockers' shadow, without compounding frame after frame; the
// terrain system's own lighting returns when the cube leaves.
TEST(SphericalLightSystems, ARedCubeBleedsOntoTheTerrainAroundIt) {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor(2);
  terrain_shadow::TerrainShadowConfig config;
  config.azimuths = 8;
  terrain_shadow::emplace_terrain_shadow_resources(world, config);
  blocker_accumulation::emplace_blocker_resources(world);
  world.resource<blocker_accumulation::BlockerSettingsResource>().refresh_period = 1;
  emplace_spherical_light_resources(world);
  world.resource<SphericalLightSettingsResource>().terrain_period = 1;
  auto& env = world.emplace_resource<components::EnvironmentLight>();
  for (auto& c : env.radiance) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
  env.version = 1;
  auto field = std::make_shared<data::HeightField>();
  field->width = field->height = 33;
  field->cell_size = 1;
  field->heights.assign(33 * 33, 0.0f);
  field->source = "flat 33";
  const ecs::Entity terrain = world.create_with(components::Terrain{field, {-16.0f, -16.0f, 0.0f}},
                                                components::TerrainLighting{});
  const data::MeshData box =
      test::box_mesh(glm::vec3(-1), glm::vec3(1), glm::vec3(0.9f, 0.1f, 0.1f));
  auto spheres = std::make_shared<std::vector<components::Sphere>>(
      std::vector<components::Sphere>{{glm::vec3(0), std::sqrt(3.0f) + 1e-3f, -1}});
  auto samples = std::make_shared<const data::ReflectorSamples>(sample_reflector(box, *spheres));
  const ecs::Entity cube = world.create_with(
      components::SphereSet{spheres}, Transform{glm::translate(glm::mat4(1), {0, 0, 1})},
      components::Reflector{samples}, components::ReflectorRadiance{});
  terrain_shadow::add_terrain_shadow_systems(schedule);
  blocker_accumulation::add_blocker_systems(schedule);
  add_spherical_light_systems(schedule);
  const auto texel = [&](int x, int y) {
    return (*world.get<components::TerrainLighting>(terrain)->rgb)[(y + 16) * 33 + x + 16];
  };
  for (int i = 0; i < 4; ++i) executor.run(schedule, world);  // states arrive, then shading
  const glm::vec3 composed =
      (*world.get<components::TerrainLighting>(terrain)->composed)[(16 + 3) * 33 + 16];
  const glm::vec3 beside = texel(0, 3);  // 3 m from the cube's centre, 2 m from its face
  EXPECT_GT(world.get<SphericalLightTerrainState>(terrain)->reached, 0u);
  EXPECT_GT(beside.x - beside.y, 0.01f);  // red on grey ground
  for (int i = 0; i < 5; ++i) executor.run(schedule, world);
  EXPECT_NEAR(texel(0, 3).x, beside.x, 1e-5f);  // not compounded
  world.get_mut<Transform>(cube)->world = glm::translate(glm::mat4(1), {0, 0, 500});
  for (int i = 0; i < 2; ++i) executor.run(schedule, world);
  EXPECT_NEAR(texel(0, 3).x, composed.x, 1e-4f * composed.x);
  EXPECT_NEAR(texel(0, 3).x, texel(0, 3).y, 1e-4f);
}

}  // namespace
}  // namespace penumbra::spherical_lights
