// The valley game's boulders and creatures on the ground (ground_bodies.h).
#include "penumbra/game/ground_bodies.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "penumbra/data/height_field.h"

namespace penumbra::game {
namespace {

using components::Terrain;

// 65 x 65 samples of 100 m around the origin; heights from f(x, y) in metres.
template <class F>
Terrain shaped_field(F f) {
  auto h = std::make_shared<data::HeightField>();
  h->width = h->height = 65;
  h->cell_size = 100.0f;
  h->heights.resize(65 * 65);
  for (int y = 0; y < 65; ++y)
    for (int x = 0; x < 65; ++x)
      h->heights[y * 65 + x] = f(-3200.0f + 100.0f * x, -3200.0f + 100.0f * y);
  return Terrain{h, {-3200.0f, -3200.0f, 0.0f}, glm::vec3(0.5f), 1.0f};
}

GroundBody roller(glm::vec2 at) {
  GroundBody b;
  b.position = at;
  b.radius = b.lift = 200.0f;
  b.id = 3;
  return b;
}

TEST(GroundBodies, ARollerRollsDownhillAndTumbles) {
  const Terrain ramp = shaped_field([](float x, float) { return 0.3f * x; });
  GroundBody b = roller({1000.0f, 0.0f});
  const glm::quat start = b.tumble;
  for (int i = 0; i < 30; ++i) step_body(b, ramp, 1.0f / 30, i, BodyConfig{});
  EXPECT_LT(b.velocity.x, -100.0f);
  EXPECT_LT(b.position.x, 1000.0f);
  EXPECT_LT(glm::dot(b.tumble, start), 0.999f);  // it turned
}

TEST(GroundBodies, ARollerAtRestInAHollowStartsAgainFromHigherGround) {
  const Terrain bowl = shaped_field([](float x, float y) { return 1e-4f * (x * x + y * y); });
  GroundBody b = roller({0.0f, 0.0f});
  const BodyConfig c;
  std::uint64_t step = 0;
  for (; step < 6 * 30 && b.restarts == 0; ++step) step_body(b, bowl, 1.0f / 30, step, c);
  EXPECT_EQ(b.restarts, 1u);
  EXPECT_GT(ground_height(bowl, b.position), 100.0f);  // the bowl's floor is 0
  EXPECT_GT(step, static_cast<std::uint64_t>(c.rest_time * 30) - 2);
}

TEST(GroundBodies, AWandererKeepsItsPaceAndStaysInTheValley) {
  const Terrain flat = shaped_field([](float, float) { return 0.0f; });
  GroundBody b;
  b.motion = BodyMotion::kWander;
  b.radius = 150.0f;
  b.id = 7;
  for (std::uint64_t i = 0; i < 30 * 120; ++i) {
    step_body(b, flat, 1.0f / 30, i, BodyConfig{});
    ASSERT_NEAR(glm::length(b.velocity), BodyConfig{}.wander_speed, 1e-2f);
    ASSERT_LT(std::abs(b.position.x), 3200.0f) << "step " << i;
    ASSERT_LT(std::abs(b.position.y), 3200.0f) << "step " << i;
  }
}

TEST(GroundBodies, ContactsPushBodiesApartAndOutOfTheOrb) {
  const Terrain flat = shaped_field([](float, float) { return 0.0f; });
  GroundBody a = roller({0.0f, 0.0f}), b = roller({100.0f, 0.0f});
  a.velocity = {300.0f, 0.0f};
  GroundBody pair[] = {a, b};
  separate_bodies(pair, {}, flat);
  EXPECT_NEAR(glm::distance(pair[0].position, pair[1].position), 400.0f, 1e-2f);
  EXPECT_LE(pair[0].velocity.x, 0.0f);  // its push into the other bounced back
  // Squeezed between the orb and another body: the orb wins exactly, the pair nearly.
  const Obstacle orb{{-250.0f, 0.0f}, 120.0f};
  GroundBody squeezed[] = {a, b};
  separate_bodies(squeezed, {&orb, 1}, flat);
  EXPECT_GE(glm::distance(squeezed[0].position, orb.centre), 320.0f - 1e-2f);
  EXPECT_GE(glm::distance(squeezed[0].position, squeezed[1].position), 0.9f * 400.0f);
  GroundBody near_orb[] = {roller({-100.0f, 0.0f})};
  separate_bodies(near_orb, {&orb, 1}, flat);
  EXPECT_GE(glm::distance(near_orb[0].position, orb.centre), 320.0f - 1e-2f);
}

TEST(GroundBodies, NonFiniteStateIsReset) {
  const Terrain flat = shaped_field([](float, float) { return 0.0f; });
  GroundBody b = roller({NAN, 0.0f});
  b.velocity = {INFINITY, 0.0f};
  step_body(b, flat, 1.0f / 30, 0, BodyConfig{});
  EXPECT_TRUE(std::isfinite(b.position.x) && std::isfinite(b.velocity.x));
}

TEST(GroundBodies, TheTransformStandsTheModelOnTheGround) {
  const Terrain ramp = shaped_field([](float x, float) { return 0.5f * x + 100.0f; });
  GroundBody b = roller({400.0f, -300.0f});
  const glm::mat4 m = body_transform(b, ramp, 2.0f, glm::vec3(1.0f, 2.0f, 3.0f));
  const glm::vec3 centre = glm::vec3(m * glm::vec4(1.0f, 2.0f, 3.0f, 1.0f));
  EXPECT_NEAR(centre.x, 400.0f, 1e-3f);
  EXPECT_NEAR(centre.z, 0.5f * 400.0f + 100.0f + 200.0f, 1e-2f);
  b.motion = BodyMotion::kWander;  // upright: model +y (glTF up) is world +z
  const glm::mat4 u = body_transform(b, ramp, 1.0f, glm::vec3(0.0f));
  const glm::vec3 up = glm::vec3(u * glm::vec4(0, 1, 0, 0));
  EXPECT_NEAR(up.z, 1.0f, 1e-5f);
}

}  // namespace
}  // namespace penumbra::game
