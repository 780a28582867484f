// The same world stepped with 1, 2 and 8 worker threads must end bit-identical: component
// bytes, entity handles and chunk order (Executor contract, executor.h).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "penumbra/components/motion.h"
#include "penumbra/game/sample_world.h"
#include "penumbra/jobs/executor.h"

namespace penumbra::jobs {
namespace {

using components::Lifetime;
using components::Position;
using components::Velocity;

template <class T>
void append_bytes(std::vector<unsigned char>& out, const T& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}

std::vector<unsigned char> snapshot(ecs::World& w) {
  std::vector<unsigned char> out;
  w.query<const Position, const Velocity, const Lifetime, const game::Irradiance>().each(
      [&](ecs::Entity e, const Position& p, const Velocity& v, const Lifetime& l,
          const game::Irradiance& irr) {
        append_bytes(out, e);
        append_bytes(out, p);
        append_bytes(out, v);
        append_bytes(out, l);
        append_bytes(out, irr);
      });
  const auto& c = w.resource<game::Centroid>();  // field by field: the struct has padding
  append_bytes(out, c.x);
  append_bytes(out, c.y);
  append_bytes(out, c.z);
  append_bytes(out, c.count);
  return out;
}

std::vector<unsigned char> run(int threads, int frames, std::size_t min_created) {
  ecs::World world;
  game::SampleWorldConfig config;
  config.particles = 40'000;
  game::populate_sample_world(world, config);
  Schedule schedule;
  game::add_sample_systems(schedule);
  Executor ex(threads);
  std::size_t created = 0;
  for (int f = 0; f < frames; ++f) created += ex.run(schedule, world).commands.created;
  EXPECT_GE(created, min_created) << "the run must exercise deferred create/destroy";
  return snapshot(world);
}

TEST(Determinism, SampleWorldIsBitIdenticalAcrossThreadCounts) {
  constexpr int kFrames = 120;  // 2 s of simulated time: many particles die and respawn
  const auto one = run(1, kFrames, 1000);
  const auto two = run(2, kFrames, 1000);
  const auto eight = run(8, kFrames, 1000);
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one.size(), two.size());
  EXPECT_EQ(one.size(), eight.size());
  EXPECT_TRUE(one == two) << "2 threads diverged from 1";
  EXPECT_TRUE(one == eight) << "8 threads diverged from 1";
}

TEST(Determinism, RepeatedRunsWithManyThreadsAgree) {
  const auto a = run(8, 90, 100);
  const auto b = run(8, 90, 100);
  EXPECT_TRUE(a == b);
}

}  // namespace
}  // namespace penumbra::jobs
