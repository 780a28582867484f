// The valley game's systems on the job graph without the renderer (valley_game.h): each rule on
// a small synthetic valley, and the committed session replayed on the real one, the same to the
// bit on 1 and 2 threads.
#include "penumbra/game/valley_game.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/data/height_field.h"
#include "penumbra/game/valley_rules.h"
#include "penumbra/jobs/executor.h"
#include "valley_replay.h"

#include <glm/geometric.hpp>

namespace penumbra::game {
namespace {

using components::FrameTime;
using components::SphericalLight;
using components::Terrain;

// A flat 6.4 km valley, a clock of 1/30 s steps and the game's systems.
struct SmallValley {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor{2};

  explicit SmallValley(const ValleyConfig& c) {
    auto f = std::make_shared<data::HeightField>();
    f->width = f->height = 65;
    f->cell_size = 100.0f;
    f->heights.assign(65 * 65, 0.0f);
    world.create_with(Terrain{f, {-3200.0f, -3200.0f, 0.0f}, glm::vec3(0.5f), 1.0f});
    world.emplace_resource<FrameTime>(FrameTime{1.0f / 30.0f, 0.0, 0});
    populate_valley(world, c);
    schedule
        .add_task("clock",
                  [](jobs::SystemContext& ctx) {
                    FrameTime& t = ctx.world().resource<FrameTime>();
                    t.elapsed += t.dt;
                    ++t.frame;
                  })
        .writes<FrameTime>();
    add_valley_systems(schedule, c);
  }
  void step(GameInput in = {}) {
    world.resource<GameInput>() = in;
    executor.run(schedule, world);
  }
  const GameState& state() { return world.resource<const GameState>(); }
  std::shared_ptr<const data::HeightField> heights() {
    std::shared_ptr<const data::HeightField> h;
    world.query<const Terrain>().each([&](const Terrain& t) { h = t.heights; });
    return h;
  }
};

const GameInput kStart{0, 0, 0, kButtonStart}, kPause{0, 0, 0, kButtonPause},
    kRestart{0, 0, 0, kButtonRestart}, kDig{0, 0, 0, kButtonDig};

TEST(ValleyGame, TheTitleWaitsForStart) {
  SmallValley v{ValleyConfig{}};
  for (int i = 0; i < 5; ++i) v.step();
  EXPECT_EQ(v.state().phase, GamePhase::kTitle);
  EXPECT_EQ(v.state().rounds, 0);
  v.step(kStart);
  EXPECT_EQ(v.state().phase, GamePhase::kPlaying);
  EXPECT_EQ(v.state().beacons_total, ValleyConfig{}.beacons);
  EXPECT_EQ(v.state().rounds, 1);
}

TEST(ValleyGame, ABeaconInReachLightsScoresAndTheLastOneWins) {
  ValleyConfig c;
  c.beacons = 1;
  c.beacon_ring_min = c.beacon_ring_max = 0.05f;  // 320 m from the orb's start: in reach
  SmallValley v{c};
  v.step(kStart);
  EXPECT_EQ(v.state().phase, GamePhase::kWon);
  EXPECT_EQ(v.state().beacons_lit, 1);
  // Lit with 120 s left (100 + 120), then the bonus for the time left after the step.
  EXPECT_EQ(v.state().score, beacon_points(120.0f) + win_bonus(120.0f - 1.0f / 30.0f));
  int lit_lights = 0;
  v.world.query<const Beacon, const SphericalLight>().each(
      [&](const Beacon& b, const SphericalLight& l) { lit_lights += b.lit && l.radius > 0; });
  EXPECT_EQ(lit_lights, 1);
  for (int i = 0; i < 10; ++i) v.step();  // the end screen holds
  EXPECT_EQ(v.state().phase, GamePhase::kWon);
}

TEST(ValleyGame, NightFallsWhenTheTimeRunsOut) {
  ValleyConfig c;
  c.time_limit = 1.0f;
  SmallValley v{c};
  auto& env = v.world.emplace_resource<components::EnvironmentLight>();
  v.step();
  EXPECT_EQ(env.intensity, 1.0f);  // daylight on the title screen
  v.step(kStart);
  for (int i = 0; i < 28; ++i) v.step();
  EXPECT_EQ(v.state().phase, GamePhase::kPlaying);
  for (int i = 0; i < 3; ++i) v.step();
  EXPECT_EQ(v.state().phase, GamePhase::kLost);
  EXPECT_EQ(v.state().score, 0);
  EXPECT_EQ(v.state().time_left, 0.0f);
  v.step();
  EXPECT_NEAR(env.intensity, c.night, 0.011f * c.night);  // night
}

TEST(ValleyGame, PauseStopsTheClockAndTheOrb) {
  SmallValley v{ValleyConfig{}};
  v.step(kStart);
  for (int i = 0; i < 10; ++i) v.step({0, 127, 0, 0});
  v.step(kPause);
  const GameState before = v.state();
  glm::vec2 at{};
  v.world.query<const Orb>().each([&](const Orb& o) { at = o.position; });
  for (int i = 0; i < 30; ++i) v.step({0, 127, 0, 0});
  EXPECT_EQ(v.state().phase, GamePhase::kPaused);
  EXPECT_EQ(v.state().time_left, before.time_left);
  v.world.query<const Orb>().each([&](const Orb& o) { EXPECT_EQ(o.position, at); });
  v.step(kPause);
  EXPECT_EQ(v.state().phase, GamePhase::kPlaying);
  EXPECT_LT(v.state().time_left, before.time_left);
}

TEST(ValleyGame, DiggingEditsTheGroundAndRestartRestoresIt) {
  SmallValley v{ValleyConfig{}};
  const auto original = v.heights();
  v.step(kStart);
  for (int i = 0; i < 20; ++i) v.step(kDig);  // one brush per half second: 2
  EXPECT_EQ(v.state().edits, 2);
  ASSERT_NE(v.heights(), original);
  EXPECT_LT(v.heights()->at(32, 32), original->at(32, 32) - 50.0f);  // a crater under the orb
  v.step(kRestart);
  EXPECT_EQ(v.heights(), original);
  EXPECT_EQ(v.state().phase, GamePhase::kPlaying);
  EXPECT_EQ(v.state().rounds, 2);
  EXPECT_EQ(v.state().edits, 0);
  EXPECT_EQ(v.state().score, 0);
  std::uint64_t version = 0;
  v.world.query<const Terrain>().each([&](const Terrain& t) { version = t.version; });
  EXPECT_EQ(version, 3u);  // two brushes and the restore: readers see every change
}

TEST(ValleyGame, AConfigItCannotPlayIsRefusedByName) {
  ecs::World empty;
  EXPECT_THROW(populate_valley(empty), std::invalid_argument);  // no terrain
  ValleyConfig c;
  c.beacons = 0;
  try {
    SmallValley v{c};
    ADD_FAILURE() << "accepted 0 beacons";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("beacons"), std::string::npos);
  }
}

// The canyon's probes (on its floor) see less sky than the valley's grid probes at a similar
// height above the ground: the probe-lit objects darken as they go in.
TEST(ValleyGame, TheCanyonDarkensTheProbesInIt) {
  ecs::World world;
  TerrainDemoConfig demo = valley_world(TerrainDemoConfig{});
  demo.probes.sky_turns = false;  // one sky step is enough here
  populate_terrain_demo(world, demo);
  const auto& cloud = *world.resource<const components::ProbeCloudResource>().cloud;
  const Terrain* terrain = nullptr;
  world.query<const Terrain>().each([&](const Terrain& t) { terrain = &t; });
  ASSERT_TRUE(terrain);
  const CanyonConfig c;
  const float width = terrain->heights->cell_size * (terrain->heights->width - 1);
  glm::vec2 a, b;
  canyon_axis(glm::vec2(terrain->origin) + 0.5f * width, width, c, a, b);
  double inside = 0, outside = 0;
  int n_in = 0, n_out = 0;
  for (std::size_t i = 0; i < cloud.probe_count(); ++i) {
    const glm::vec3 p = cloud.positions[i];
    const float above = p.z - ground_height(*terrain, glm::vec2(p));
    const glm::vec2 ab = b - a;
    const float t = std::clamp(glm::dot(glm::vec2(p) - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
    const float from_axis = glm::length(glm::vec2(p) - (a + t * ab));
    const float* sh = cloud.probe_sh(i);
    const std::size_t per = static_cast<std::size_t>(cloud.bands * cloud.bands);
    const double dc = 0.2126 * sh[0] + 0.7152 * sh[per] + 0.0722 * sh[2 * per];
    if (from_axis < 50.0f && above < 150.0f) inside += dc, ++n_in;
    if (from_axis > 3 * c.half_width && above < 150.0f) outside += dc, ++n_out;
  }
  ASSERT_GT(n_in, 5);
  ASSERT_GT(n_out, 20);
  std::printf("probe irradiance (DC luminance): canyon floor %.4f (%d probes), valley %.4f (%d)\n",
              inside / n_in, n_in, outside / n_out, n_out);
  EXPECT_LT(inside / n_in, 0.85 * (outside / n_out))
      << "canyon " << inside / n_in << ", valley " << outside / n_out;
}

// The committed session (game/sessions/dusk_run.pinput) on the real valley with every lighting
// system, as `./penumbra play --no-render` runs it.
struct Outcome {
  GameState state;
  Orb orb;
  std::uint64_t terrain_version = 0;
};

Outcome replay(int threads) {
  TerrainDemoConfig demo;
  demo.probes.count = 0;  // the floaters only read the game's world: probe_demo_test covers them
  test::ValleyReplay r(threads, demo);
  for (std::size_t i = 0, n = r.steps(); i < n; ++i) r.step();
  ecs::World& world = r.world;
  Outcome o;
  o.state = world.resource<const GameState>();
  world.query<const Orb>().each([&](const Orb& orb) { o.orb = orb; });
  world.query<const Terrain>().each([&](const Terrain& t) { o.terrain_version = t.version; });
  return o;
}

TEST(ValleyGame, TheRecordedSessionEndsTheSameOnOneAndTwoThreads) {
  const Outcome one = replay(1), two = replay(2);
  EXPECT_EQ(one.state.phase, GamePhase::kWon);  // the session was recorded winning
  EXPECT_EQ(one.state.beacons_lit, one.state.beacons_total);
  EXPECT_GT(one.state.edits, 0);
  EXPECT_EQ(two.state.phase, one.state.phase);
  EXPECT_EQ(two.state.score, one.state.score);
  EXPECT_EQ(two.state.steps, one.state.steps);
  EXPECT_EQ(two.state.edits, one.state.edits);
  EXPECT_EQ(two.terrain_version, one.terrain_version);
  // Bit-identical, not close: the rules read nothing the thread count can change.
  EXPECT_EQ(std::memcmp(&two.orb, &one.orb, sizeof(Orb)), 0);
  EXPECT_EQ(std::memcmp(&two.state.time_left, &one.state.time_left, sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(&two.state.heading, &one.state.heading, sizeof(float)), 0);
}

}  // namespace
}  // namespace penumbra::game
