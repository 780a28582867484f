// The local lights' route to receivers (components::LocalLightRouting): through blockers.shade as
// SH radiance (kBlockerSh, the default) or through spherical_lights.gather as spherical lights
// shadowed by every blocker sphere (kSphereLightGather, [Guerrero08] eq. 13-18 and 23-24), into
// ReceiverLighting::local. Against the exact answer: a lamp over a ground of receivers, a
// blocker hiding it wholly from the receiver under it.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/constants.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/transform.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/spherical_lights/spherical_light_systems.h"

namespace penumbra::spherical_lights {
namespace {

using components::LocalLightPath;
using components::ReceiverLighting;

constexpr float kRadiance = 10.0f;
const glm::vec3 kLamp(0.0f, 0.0f, 6.0f);
constexpr float kLampRadius = 0.5f;

// Receivers on the ground at x = 0 (under the blocker and the lamp) and x = 3 (in the open);
// a 1 m blocker sphere at height 3 between the lamp and x = 0; no environment light.
struct RoutingScene {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor{2};
  ecs::Entity ground;
  explicit RoutingScene(LocalLightPath path) {
    blocker_accumulation::emplace_blocker_resources(world);
    emplace_spherical_light_resources(world);
    world.emplace_resource<components::EnvironmentLight>();  // black
    world.emplace_resource<components::LocalLightRouting>(components::LocalLightRouting{path});
    auto points = std::make_shared<std::vector<glm::vec3>>(
        std::vector<glm::vec3>{{0.0f, 0.0f, 0.0f}, {3.0f, 0.0f, 0.0f}});
    auto normals = std::make_shared<std::vector<glm::vec3>>(2, glm::vec3(0, 0, 1));
    ground = world.create_with(components::Receiver{points, normals}, components::Transform{},
                               ReceiverLighting{});
    auto spheres = std::make_shared<std::vector<components::Sphere>>(
        std::vector<components::Sphere>{{glm::vec3(0), 1.0f, -1}});
    world.create_with(components::SphereSet{spheres},
                      components::Transform{glm::translate(glm::mat4(1), {0, 0, 3})});
    world.create_with(components::SphericalLight{kLamp, kLampRadius, glm::vec3(kRadiance)});
    blocker_accumulation::add_blocker_systems(schedule);
    add_spherical_light_systems(schedule);
    for (int i = 0; i < 2; ++i) executor.run(schedule, world);
  }
  const ReceiverLighting& lighting() { return *world.get<ReceiverLighting>(ground); }
};

// Exact irradiance from a uniform sphere wholly above the receiver's horizon: pi L (r/d)^2 cos.
float exact_open() {
  const glm::vec3 to = kLamp - glm::vec3(3, 0, 0);
  const float d = glm::length(to);
  return kPi * kRadiance * (kLampRadius / d) * (kLampRadius / d) * (to.z / d);
}

// Unoccluded, straight under the lamp.
float exact_under() {
  return kPi * kRadiance * (kLampRadius / kLamp.z) * (kLampRadius / kLamp.z);
}

// Measured (this scene): in the open 0.130 against 0.156 exact (-17%: the blocker's SH shadow,
// 18 degrees away, leaks over it); under the blocker 0.134, 61% of the unoccluded 0.218 where
// the exact answer is 0 (the 4-band visibility cannot make a shadow this sharp).
TEST(LocalLightRouting, ThroughTheBlockerSystemByDefault) {
  RoutingScene s(LocalLightPath::kBlockerSh);
  const ReceiverLighting& l = s.lighting();
  ASSERT_TRUE(l.irradiance);
  EXPECT_FALSE(l.local);
  EXPECT_NEAR((*l.irradiance)[1].x, exact_open(), 0.2f * exact_open());
  EXPECT_GT((*l.irradiance)[0].x, 0.4f * exact_under()) << "the blur this route has";
}

// Measured: in the open exact to 1e-5 (the tabulated w_theta of a uniform sphere); under the
// blocker 0.032, 15% of the unoccluded (eq. 23-24's exponentials of the band-limited log
// visibility over the lamp's cap).
TEST(LocalLightRouting, ThroughTheSphereLightGatherWithSharperShadows) {
  RoutingScene s(LocalLightPath::kSphereLightGather);
  const ReceiverLighting& l = s.lighting();
  ASSERT_TRUE(l.irradiance && l.local);
  EXPECT_NEAR((*l.irradiance)[1].x, 0.0f, 1e-4f) << "blockers.shade leaves the lamp out";
  EXPECT_NEAR((*l.local)[1].x, exact_open(), 0.01f * exact_open());
  EXPECT_LT((*l.local)[0].x, 0.2f * exact_under());
  EXPECT_EQ(s.world.resource<SphericalLightField>().local_lights, 1u);
}

TEST(LocalLightRouting, WithoutLocalLightsTheTermIsCleared) {
  RoutingScene s(LocalLightPath::kSphereLightGather);
  std::vector<ecs::Entity> lamps;
  s.world.query<const components::SphericalLight>().each(
      [&](ecs::Entity e, const components::SphericalLight&) { lamps.push_back(e); });
  for (ecs::Entity e : lamps) s.world.destroy(e);
  s.executor.run(s.schedule, s.world);
  EXPECT_FALSE(s.lighting().local);
  EXPECT_FALSE(s.world.resource<SphericalLightField>().local_gather);
}

}  // namespace
}  // namespace penumbra::spherical_lights
