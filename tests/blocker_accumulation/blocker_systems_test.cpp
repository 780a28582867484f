#include "penumbra/systems/blocker_accumulation/blocker_systems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "common/frame_work.h"
#include "common/stability.h"
#include "penumbra/components/camera.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"

namespace penumbra::blocker_accumulation {
namespace {

using components::Receiver;
using components::ReceiverLighting;
using components::Sphere;
using components::SphereSet;
using components::Transform;

// A 21 x 21 grid of upward receivers on z = 0 (20 m square) and a two-sphere blocker.
struct Scene {
  ecs::World world;
  ecs::Entity ground, boulder;
  jobs::Schedule schedule;
  jobs::Executor executor{2};
  Scene() {
    emplace_blocker_resources(world);
    world.resource<BlockerSettingsResource>().refresh_period = 1;  // every frame
    auto& env = world.emplace_resource<components::EnvironmentLight>();
    env.radiance[0][0] = env.radiance[1][0] = env.radiance[2][0] =
        std::sqrt(4 * std::numbers::pi_v<float>);  // uniform unit sky
    auto points = std::make_shared<std::vector<glm::vec3>>();
    for (int y = 0; y <= 20; ++y)
      for (int x = 0; x <= 20; ++x) points->push_back({x - 10.0f, y - 10.0f, 0.0f});
    auto normals = std::make_shared<std::vector<glm::vec3>>(points->size(), glm::vec3(0, 0, 1));
    ground = world.create_with(Receiver{points, normals}, Transform{}, ReceiverLighting{});
    auto spheres = std::make_shared<std::vector<Sphere>>(
        std::vector<Sphere>{{{0, 0, 0}, 2.0f, -1}, {{0, 0, 1.5f}, 1.2f, -1}});
    boulder = world.create_with(SphereSet{spheres},
                                Transform{glm::translate(glm::mat4(1), {0, 0, 2.5f})});
    add_blocker_systems(schedule);
  }
  const std::vector<glm::vec3>& irradiance() {
    return *world.get<ReceiverLighting>(ground)->irradiance;
  }
  glm::vec3 at(int x, int y) {
    return irradiance()[static_cast<std::size_t>(y + 10) * 21 + x + 10];
  }
};

TEST(BlockerSystems, BlockerShadowsTheGroundUnderItAndFollowsItsTransform) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  ASSERT_NE(s.world.get<ReceiverLighting>(s.ground)->irradiance, nullptr);
  const float pi = std::numbers::pi_v<float>;
  EXPECT_LT(s.at(0, 0).x, 0.7f * pi);           // under the boulder
  EXPECT_NEAR(s.at(10, 10).x, pi, 0.03f * pi);  // far corner: open sky
  EXPECT_EQ(s.world.get<ReceiverLighting>(s.ground)->visibility->size(), 441u);
  EXPECT_EQ(s.world.resource<BlockerField>().receivers, 441u);

  s.world.get_mut<Transform>(s.boulder)->world = glm::translate(glm::mat4(1), {8, 8, 2.5f});
  s.executor.run(s.schedule, s.world);
  EXPECT_NEAR(s.at(0, 0).x, pi, 0.05f * pi);
  EXPECT_LT(s.at(8, 8).x, 0.7f * pi);
}

// EnvironmentLight::intensity (the valley game's dusk) scales the sky's light at every receiver,
// shadowed or not.
TEST(BlockerSystems, TheSkysIntensityScalesTheReceiversLight) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  const std::vector<glm::vec3> full = s.irradiance();
  s.world.resource<components::EnvironmentLight>().intensity = 0.25f;
  s.executor.run(s.schedule, s.world);
  const std::vector<glm::vec3>& dimmed = s.irradiance();
  ASSERT_EQ(dimmed.size(), full.size());
  for (std::size_t i = 0; i < full.size(); ++i)
    ASSERT_NEAR(dimmed[i].y, 0.25f * full[i].y, 1e-5f * (1 + full[i].y)) << "receiver " << i;
}

// A Material makes the outgoing radiance: albedo E / pi when Lambertian; with a Phong exponent,
// the albedo times the shadowed lobe towards the camera, which moves with the camera.
TEST(BlockerSystems, MaterialShadesDiffuseOrGlossyTowardsTheCamera) {
  Scene s;
  s.world.add(s.ground, components::Material{{0.5f, 0.25f, 0.1f}, 0.0f});
  s.executor.run(s.schedule, s.world);
  const ReceiverLighting* l = s.world.get<ReceiverLighting>(s.ground);
  ASSERT_NE(l->radiance, nullptr);
  const std::size_t corner = 440;  // (10, 10): open sky
  const glm::vec3 e = (*l->irradiance)[corner];
  const glm::vec3 expected = glm::vec3(0.5f, 0.25f, 0.1f) * e * std::numbers::inv_pi_v<float>;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR((*l->radiance)[corner][c], expected[c], 1e-5f);

  // Glossy under a sky brighter towards +x: the reflection is brighter seen from -x.
  auto& env = s.world.resource<components::EnvironmentLight>();
  for (int c = 0; c < 3; ++c) env.radiance[c][sh::index(1, 1)] = 1.5f;
  s.world.get_mut<components::Material>(s.ground)->phong_exponent = 8;
  auto& camera = s.world.emplace_resource<components::Camera>();
  camera.position = {-30, 10, 20};  // sees the corner's reflection towards +x
  s.executor.run(s.schedule, s.world);
  const float towards_bright = (*s.world.get<ReceiverLighting>(s.ground)->radiance)[corner].x;
  camera.position = {50, 10, 20};
  s.executor.run(s.schedule, s.world);
  const float towards_dark = (*s.world.get<ReceiverLighting>(s.ground)->radiance)[corner].x;
  EXPECT_GT(towards_bright, 1.3f * towards_dark);
  EXPECT_EQ(s.world.resource<BlockerField>().lobes.size(), 1u);  // one lobe per exponent

  s.world.get_mut<components::Material>(s.ground)->phong_exponent = -1;  // named, Lambertian
  s.executor.run(s.schedule, s.world);
  ASSERT_EQ(s.world.resource<BlockerField>().errors.size(), 1u);
  EXPECT_NE(s.world.resource<BlockerField>().errors[0].find("Material"), std::string::npos);
  const ReceiverLighting* after = s.world.get<ReceiverLighting>(s.ground);
  EXPECT_NEAR((*after->radiance)[corner].x,
              (*after->irradiance)[corner].x * std::numbers::inv_pi_v<float>, 1e-5f);
}

// A set whose spheres name parents ([Ren06] hierarchy): each root with descendants becomes one
// group, the root its bound and the leaves its blockers; bad parent indices are named and the
// set is used flat.
TEST(BlockerSystems, ParentIndicesMakeTheGroups) {
  Scene s;
  // Root 0 (r 3) over leaves 1 and 2; root 3 alone.
  auto tree = std::make_shared<std::vector<Sphere>>(std::vector<Sphere>{
      {{0, 0, 0}, 3.0f, -1}, {{-1, 0, 0}, 1.5f, 0}, {{1, 0, 0}, 1.5f, 0}, {{0, 6, 0}, 1.0f, -1}});
  s.world.get_mut<SphereSet>(s.boulder)->spheres = tree;
  s.executor.run(s.schedule, s.world);
  const BlockerField& field = s.world.resource<BlockerField>();
  EXPECT_TRUE(field.errors.empty());
  const auto blockers = field.accumulation->blockers();
  ASSERT_EQ(blockers.size(), 3u);  // the two leaves and the lone root; root 0 is only a bound
  EXPECT_FLOAT_EQ(blockers[0].radius, 1.5f);
  EXPECT_FLOAT_EQ(blockers[2].radius, 1.0f);
  EXPECT_LT(s.at(0, 0).x, 0.8f * std::numbers::pi_v<float>);  // still shadows

  auto bad = std::make_shared<std::vector<Sphere>>(*tree);
  (*bad)[1].parent = 7;  // out of range
  s.world.get_mut<SphereSet>(s.boulder)->spheres = bad;
  s.executor.run(s.schedule, s.world);
  ASSERT_EQ(s.world.resource<BlockerField>().errors.size(), 1u);
  EXPECT_NE(s.world.resource<BlockerField>().errors[0].find("parent 7"), std::string::npos);
  EXPECT_EQ(s.world.resource<BlockerField>().accumulation->blockers().size(), 4u);  // flat

  (*bad)[1].parent = 0;
  (*bad)[0].parent = 1;  // 0 -> 1 -> 0: a cycle
  s.world.get_mut<SphereSet>(s.boulder)->spheres = std::make_shared<std::vector<Sphere>>(*bad);
  s.executor.run(s.schedule, s.world);
  ASSERT_EQ(s.world.resource<BlockerField>().errors.size(), 1u);
  EXPECT_NE(s.world.resource<BlockerField>().errors[0].find("cycle"), std::string::npos);
}

// With a refresh period of 4 a receiving entity is re-shaded once in every 4 frames: a moved
// blocker shows within 4 frames, and not every frame pays for every receiver.
TEST(BlockerSystems, RefreshPeriodSpreadsReceiversOverFrames) {
  Scene s;
  s.world.resource<BlockerSettingsResource>().refresh_period = 4;
  s.executor.run(s.schedule, s.world);  // a new receiver is shaded at once
  ASSERT_NE(s.world.get<ReceiverLighting>(s.ground)->irradiance, nullptr);
  const float under = s.at(0, 0).x;
  s.world.get_mut<Transform>(s.boulder)->world = glm::translate(glm::mat4(1), {8, 8, 2.5f});
  int frames = 0, shaded = 0;
  while (s.at(0, 0).x == under && frames < 8) {
    s.executor.run(s.schedule, s.world);
    ++frames;
    shaded += s.world.resource<BlockerField>().receivers > 0;
  }
  EXPECT_LE(frames, 4);
  EXPECT_GT(s.at(0, 0).x, under);
  EXPECT_EQ(shaded, 1);
}

// The frame table's work report (jobs::report_work) of blockers.shade: receivers re-shaded and
// receivers left to a later frame. It is a budget, not a change test: with the budget for one
// receiver, every new receiver first, then one a frame round robin, even when nothing moved.
TEST(BlockerSystems, ReportsTheReceiversItSkipsPerFrame) {
  Scene s;
  for (int i = 0; i < 2; ++i) {
    const Receiver& r = *s.world.get<Receiver>(s.ground);
    s.world.create_with(Receiver{r.points, r.normals}, Transform{}, ReceiverLighting{});
  }
  s.world.resource<BlockerSettingsResource>().receiver_budget = 1;
  auto shade = [&] {
    return penumbra::test::system_timing(s.executor.last_frame(), "blockers.shade");
  };
  s.executor.run(s.schedule, s.world);
  EXPECT_TRUE(shade().reported);
  EXPECT_EQ(shade().done, 3u) << "new receivers are shaded at once";
  EXPECT_EQ(shade().skipped, 0u);
  for (int f = 0; f < 3; ++f) {
    s.executor.run(s.schedule, s.world);
    EXPECT_EQ(shade().done, 1u);
    EXPECT_EQ(shade().skipped, 2u);
  }
  EXPECT_FALSE(penumbra::test::system_timing(s.executor.last_frame(), "blockers.gather").reported);
}

TEST(BlockerSystems, NonFiniteInputIsNamedAndLeftOut) {
  PENUMBRA_STABILITY(
      "a non-finite transform or receiver point in the ECS",
      "the entity is named in BlockerField::errors and left out for the frame; lighting kept", "-");
  Scene s;
  s.executor.run(s.schedule, s.world);
  const glm::vec3 before = s.at(0, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  s.world.get_mut<Transform>(s.boulder)->world[3][0] = nan;
  s.executor.run(s.schedule, s.world);
  const auto& errors = s.world.resource<BlockerField>().errors;
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("entity " + std::to_string(s.boulder.index)), std::string::npos)
      << errors[0];
  EXPECT_GT(s.at(0, 0).x, before.x);  // the boulder is gone for this frame

  auto bad = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(nan, 0, 0));
  auto up = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(0, 0, 1));
  const ecs::Entity e = s.world.create_with(Receiver{bad, up}, Transform{}, ReceiverLighting{});
  s.executor.run(s.schedule, s.world);
  bool named = false;
  for (const std::string& m : s.world.resource<BlockerField>().errors)
    named |= m.find("entity " + std::to_string(e.index)) != std::string::npos;
  EXPECT_TRUE(named);
  EXPECT_EQ(s.world.get<ReceiverLighting>(e)->irradiance, nullptr);
}

// With the terrain shadow system: the blocker darkens the terrain's texels under it, and the
// terrain system's own lighting comes back when the blocker leaves.
TEST(BlockerSystems, BlockerShadowsTheTerrainAndTheBaseReturns) {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor(2);
  terrain_shadow::TerrainShadowConfig config;
  config.azimuths = 8;
  terrain_shadow::emplace_terrain_shadow_resources(world, config);
  emplace_blocker_resources(world);
  world.resource<BlockerSettingsResource>().refresh_period = 1;
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
  auto spheres = std::make_shared<std::vector<Sphere>>(std::vector<Sphere>{{{0, 0, 0}, 2.0f, -1}});
  const ecs::Entity boulder =
      world.create_with(SphereSet{spheres}, Transform{glm::translate(glm::mat4(1), {0, 0, 3})});
  // A receiver 1 m above the ground, facing sideways: the ground below hides half its lobe
  // ([Giraud] sec. 4.1 cast shadow); what the renderer shows is its VertexLighting.
  auto point = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(0, 0, 0));
  auto side = std::make_shared<std::vector<glm::vec3>>(1, glm::vec3(1, 0, 0));
  const ecs::Entity post =
      world.create_with(Receiver{point, side}, Transform{glm::translate(glm::mat4(1), {10, 10, 1})},
                        ReceiverLighting{}, components::VertexLighting{});
  terrain_shadow::add_terrain_shadow_systems(schedule);
  add_blocker_systems(schedule);
  const auto texel = [&](int x, int y) {
    return (*world.get<components::TerrainLighting>(terrain)->rgb)[(y + 16) * 33 + x + 16].x;
  };
  for (int i = 0; i < 3; ++i) executor.run(schedule, world);  // state arrives, then shading
  const float open = (*world.get<BlockerTerrainState>(terrain)->base)[16 * 33 + 16].x;
  EXPECT_GT(open, 0.0f);
  EXPECT_LT(texel(0, 0), 0.75f * open);
  EXPECT_GT(world.get<BlockerTerrainState>(terrain)->reached, 0u);
  const float pi = std::numbers::pi_v<float>;
  const float e_post = (*world.get<ReceiverLighting>(post)->irradiance)[0].x;
  std::printf("sideways receiver over flat ground: E = %.3f pi (open sky 1, ground-hidden 0.5)\n",
              e_post / pi);
  EXPECT_LT(e_post, 0.75f * pi);
  EXPECT_GT(e_post, 0.35f * pi);
  EXPECT_NEAR((*world.get<components::VertexLighting>(post)->rgb)[0].x, e_post / pi, 1e-6f);
  world.get_mut<Transform>(boulder)->world = glm::translate(glm::mat4(1), {0, 0, 500});
  executor.run(schedule, world);
  EXPECT_NEAR(texel(0, 0), open, 1e-4f * open);
  EXPECT_EQ(world.get<components::TerrainLighting>(terrain)->rgb,
            world.get<BlockerTerrainState>(terrain)->base);
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
