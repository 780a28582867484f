#include "penumbra/systems/spherical_lights/spherical_light_systems.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/reflector.h"
#include "penumbra/components/reflector_radiance.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/transform.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
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

}  // namespace
}  // namespace penumbra::spherical_lights
