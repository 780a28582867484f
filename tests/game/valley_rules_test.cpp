// The valley game's rules without the ECS (valley_rules.h): phases, the orb's motion, points.
#include "penumbra/game/valley_rules.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include <glm/geometric.hpp>

#include "penumbra/data/height_field.h"

namespace penumbra::game {
namespace {

using components::Terrain;

// A 65 x 65 field of 100 m cells centred on the origin: flat, or a ramp rising along +x.
Terrain field(float slope = 0.0f) {
  auto f = std::make_shared<data::HeightField>();
  f->width = f->height = 65;
  f->cell_size = 100.0f;
  f->heights.resize(65 * 65);
  for (int y = 0; y < 65; ++y)
    for (int x = 0; x < 65; ++x) f->heights[y * 65 + x] = slope * 100.0f * x;
  return Terrain{f, {-3200.0f, -3200.0f, 0.0f}, glm::vec3(0.5f), 1.0f};
}

GameInput stick(float x, float y) {
  return {quantize_axis(x), quantize_axis(y), 0, 0};
}

TEST(ValleyRules, PhasesFollowTheButtons) {
  const GameInput none{}, start{0, 0, 0, kButtonStart}, pause{0, 0, 0, kButtonPause},
      restart{0, 0, 0, kButtonRestart};
  using P = GamePhase;
  EXPECT_EQ(next_phase(P::kTitle, none).phase, P::kTitle);
  EXPECT_TRUE(next_phase(P::kTitle, start).new_round);
  EXPECT_EQ(next_phase(P::kTitle, start).phase, P::kPlaying);
  EXPECT_EQ(next_phase(P::kTitle, pause).phase, P::kTitle);
  EXPECT_EQ(next_phase(P::kPlaying, pause).phase, P::kPaused);
  EXPECT_FALSE(next_phase(P::kPlaying, pause).new_round);
  EXPECT_EQ(next_phase(P::kPaused, pause).phase, P::kPlaying);
  EXPECT_EQ(next_phase(P::kPaused, none).phase, P::kPaused);
  EXPECT_TRUE(next_phase(P::kPaused, restart).new_round);
  EXPECT_TRUE(next_phase(P::kPlaying, restart).new_round);
  EXPECT_FALSE(next_phase(P::kPlaying, start).new_round);  // start does nothing mid-round
  for (P end : {P::kWon, P::kLost}) {
    EXPECT_EQ(next_phase(end, none).phase, end);
    EXPECT_EQ(next_phase(end, pause).phase, end);
    EXPECT_TRUE(next_phase(end, start).new_round);
    EXPECT_TRUE(next_phase(end, restart).new_round);
  }
}

TEST(ValleyRules, TheStickPushesAlongTheHeadingAndDragLimitsTheSpeed) {
  const Terrain t = field();
  const ValleyConfig c;
  Orb orb;
  const float heading = std::numbers::pi_v<float> / 2;  // facing +y
  for (int i = 0; i < 30; ++i) step_orb(orb, t, stick(0, 1), heading, 1.0f / 30, c, {});
  EXPECT_GT(orb.velocity.y, 500.0f);
  EXPECT_NEAR(orb.velocity.x, 0.0f, 1e-3f);
  Orb right;  // stick to the right while facing +y: towards +x
  for (int i = 0; i < 5; ++i) step_orb(right, t, stick(1, 0), heading, 1.0f / 30, c, {});
  EXPECT_GT(right.velocity.x, 0.0f);
  for (int i = 0; i < 600; ++i) step_orb(orb, t, stick(0, 1), heading, 1.0f / 30, c, {});
  EXPECT_LE(glm::length(orb.velocity), c.orb_accel / c.orb_drag * 1.001f);
  // Held against the field's edge: inside by the orb's radius, not moving out.
  EXPECT_NEAR(orb.position.y, 3200.0f - c.orb_radius, 1e-2f);
  EXPECT_EQ(orb.velocity.y, 0.0f);
}

TEST(ValleyRules, SlopesPullDownhill) {
  const Terrain ramp = field(0.3f);
  EXPECT_NEAR(ground_slope(ramp, {0, 0}).x, 0.3f, 1e-4f);
  EXPECT_NEAR(ground_height(ramp, {-3200.0f, 0.0f}), 0.0f, 1e-3f);
  EXPECT_NEAR(ground_height(ramp, {50.0f, 0.0f}), 0.3f * 3250.0f, 0.1f);
  Orb orb;
  for (int i = 0; i < 30; ++i) step_orb(orb, ramp, {}, 0.0f, 1.0f / 30, ValleyConfig{}, {});
  EXPECT_LT(orb.velocity.x, -50.0f);
  EXPECT_LT(orb.position.x, 0.0f);
}

TEST(ValleyRules, ObstaclesPushTheOrbOutAndStopItGoingIn) {
  const Terrain t = field();
  const ValleyConfig c;
  Orb orb;
  orb.position = {-400.0f, 0.0f};
  orb.velocity = {800.0f, 0.0f};
  const Obstacle boulder{{0.0f, 0.0f}, 250.0f};
  bool touched = false;
  for (int i = 0; i < 20; ++i)
    touched |= step_orb(orb, t, stick(0, 1), 0.0f, 1.0f / 30, c, {&boulder, 1});
  EXPECT_TRUE(touched);
  EXPECT_GE(glm::distance(orb.position, boulder.centre), 250.0f + c.orb_radius - 1e-2f);
}

TEST(ValleyRules, NonFiniteStateComesToRestAtTheStart) {
  const Terrain t = field();
  Orb orb;
  orb.start = {100.0f, 200.0f};
  orb.position = {NAN, 0.0f};
  orb.velocity = {1.0f, 1.0f};
  EXPECT_FALSE(step_orb(orb, t, stick(1, 1), 0.0f, 1.0f / 30, ValleyConfig{}, {}));
  EXPECT_EQ(orb.position, orb.start);
  EXPECT_EQ(orb.velocity, glm::vec2(0.0f));
  Orb still;
  step_orb(still, t, stick(1, 1), NAN, 1.0f / 30, ValleyConfig{}, {});
  EXPECT_EQ(still.velocity, glm::vec2(0.0f));
}

TEST(ValleyRules, PointsRewardTimeLeft) {
  EXPECT_EQ(beacon_points(42.7f), 142);
  EXPECT_EQ(beacon_points(-3.0f), 100);
  EXPECT_EQ(win_bonus(12.9f), 120);
  EXPECT_EQ(win_bonus(0.0f), 0);
}

TEST(ValleyRules, DuskFallsInWholeStepsFromDaylightToNight) {
  EXPECT_EQ(dusk_intensity(120.0f, 120.0f, 0.06f, 1.02f), 1.0f);
  EXPECT_NEAR(dusk_intensity(0.0f, 120.0f, 0.06f, 1.02f), 0.06f, 0.06f * 0.011f);
  EXPECT_NEAR(dusk_intensity(60.0f, 120.0f, 0.06f, 1.02f), std::sqrt(0.06f), 0.01f);
  // Whole steps: the value changes about once a second, not every frame.
  int changes = 0;
  float last = 1.0f;
  for (int f = 0; f <= 3600; ++f) {
    const float k = dusk_intensity(120.0f - f / 30.0f, 120.0f, 0.06f, 1.02f);
    EXPECT_LE(k, last);
    changes += k != last;
    last = k;
  }
  EXPECT_NEAR(changes, 142, 2);                                 // ln(1 / 0.06) / ln(1.02)
  EXPECT_EQ(dusk_intensity(10.0f, 0.0f, 0.06f, 1.02f), 1.0f);   // no limit: no dusk
  EXPECT_EQ(dusk_intensity(10.0f, 120.0f, 0.06f, 1.0f), 1.0f);  // no step
}

TEST(ValleyRules, BeaconSitesAreReproducibleAndOnTheRing) {
  const Terrain t = field();
  ValleyConfig c;
  const auto a = beacon_sites(t, c), b = beacon_sites(t, c);
  ASSERT_EQ(a.size(), static_cast<std::size_t>(c.beacons));
  EXPECT_EQ(a, b);
  for (const glm::vec2 p : a) {
    EXPECT_GE(glm::length(p), 6400.0f * c.beacon_ring_min - 1e-2f);
    EXPECT_LE(glm::length(p), 6400.0f * c.beacon_ring_max + 1e-2f);
  }
  c.seed = 2;
  EXPECT_NE(beacon_sites(t, c), a);
  EXPECT_TRUE(beacon_sites(Terrain{}, c).empty());
}

}  // namespace
}  // namespace penumbra::game
