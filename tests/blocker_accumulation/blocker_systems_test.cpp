#include "penumbra/systems/blocker_accumulation/blocker_systems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/transform.h"
#include "penumbra/jobs/executor.h"

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
  glm::vec3 at(int x, int y) { return irradiance()[static_cast<std::size_t>(y + 10) * 21 + x + 10]; }
};

TEST(BlockerSystems, BlockerShadowsTheGroundUnderItAndFollowsItsTransform) {
  Scene s;
  s.executor.run(s.schedule, s.world);
  ASSERT_NE(s.world.get<ReceiverLighting>(s.ground)->irradiance, nullptr);
  const float pi = std::numbers::pi_v<float>;
  EXPECT_LT(s.at(0, 0).x, 0.7f * pi);          // under the boulder
  EXPECT_NEAR(s.at(10, 10).x, pi, 0.03f * pi);  // far corner: open sky
  EXPECT_EQ(s.world.get<ReceiverLighting>(s.ground)->visibility->size(), 441u);
  EXPECT_EQ(s.world.resource<BlockerField>().receivers, 441u);

  s.world.get_mut<Transform>(s.boulder)->world = glm::translate(glm::mat4(1), {8, 8, 2.5f});
  s.executor.run(s.schedule, s.world);
  EXPECT_NEAR(s.at(0, 0).x, pi, 0.05f * pi);
  EXPECT_LT(s.at(8, 8).x, 0.7f * pi);
}

TEST(BlockerSystems, NonFiniteInputIsNamedAndLeftOut) {
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

}  // namespace
}  // namespace penumbra::blocker_accumulation
