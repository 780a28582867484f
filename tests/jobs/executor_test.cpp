#include "penumbra/jobs/executor.h"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "common/stability.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/motion.h"

namespace penumbra::jobs {
namespace {

using components::FrameTime;
using components::Lifetime;
using components::Position;
using components::Velocity;

struct Counter {
  int value = 0;
};
struct Visited {
  int count = 0;
};

class ExecutorTest : public ::testing::TestWithParam<int> {};

// Two systems: "bump" increments the Counter resource, "read" then records its value.
struct BumpAndRead {
  ecs::World w;
  std::vector<int> seen;
  Schedule s;
  Executor ex;

  explicit BumpAndRead(int threads) : ex(threads) {
    w.emplace_resource<Counter>();
    s.add_task("bump", [](SystemContext& ctx) {
       ++ctx.world().resource<Counter>().value;
     }).writes<Counter>();
    s.add_task("read", [this](SystemContext& ctx) {
       seen.push_back(ctx.world().resource<const Counter>().value);
     }).reads<Counter>();
  }
  void frame() { ex.run(s, w); }
};

TEST_P(ExecutorTest, WriterRunsBeforeReaderEveryFrame) {
  BumpAndRead t(GetParam());
  for (int f = 0; f < 50; ++f) t.frame();
  ASSERT_EQ(t.seen.size(), 50u);
  for (int f = 0; f < 50; ++f) EXPECT_EQ(t.seen[f], f + 1);
}

// A paused system runs nothing (its output keeps its last value), still orders its readers, and
// picks up where it was when resumed; an unknown name cannot be paused.
TEST_P(ExecutorTest, APausedSystemRunsNothingUntilResumed) {
  BumpAndRead t(GetParam());
  t.frame();
  EXPECT_TRUE(t.s.set_paused("bump", true));
  EXPECT_TRUE(t.s.paused("bump"));
  t.frame();
  t.frame();
  EXPECT_TRUE(t.ex.last_frame().systems[0].paused);
  EXPECT_FALSE(t.ex.last_frame().systems[1].paused);
  EXPECT_TRUE(t.s.set_paused("bump", false));
  t.frame();
  EXPECT_FALSE(t.ex.last_frame().systems[0].paused);
  EXPECT_EQ(t.seen, (std::vector<int>{1, 1, 1, 2}));
  EXPECT_FALSE(t.s.set_paused("nope", true));
}

TEST_P(ExecutorTest, EveryEntityVisitedOncePerFrame) {
  ecs::World w;
  for (int i = 0; i < 100000; ++i) w.create_with(Visited{});
  Schedule s;
  s.add_each<Visited>("visit", [](Visited& v) { ++v.count; });
  Executor ex(GetParam());
  for (int f = 0; f < 3; ++f) ex.run(s, w);
  int bad = 0;
  w.query<const Visited>().each([&](const Visited& v) { bad += v.count != 3; });
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(ex.last_frame().systems[0].entities, 100000u);
  EXPECT_GT(ex.last_frame().systems[0].chunks, 1u);
}

TEST_P(ExecutorTest, SpawnedEntitiesAreVisibleAfterTheSyncPoint) {
  ecs::World w;
  for (int i = 0; i < 1000; ++i) w.create_with(Position{}, Lifetime{float(i % 4)});
  std::atomic<std::size_t> seen_by_counter{0};
  Schedule s;
  // Each entity with no time left is destroyed and replaced by one with 3 frames.
  s.add_chunks<Lifetime>("age", [](SystemContext& ctx, const ecs::ChunkView<Lifetime>& c) {
     auto life = c.get<Lifetime>();
     auto ents = c.entities();
     for (std::size_t i = 0; i < c.size(); ++i) {
       life[i].seconds -= 1;
       if (life[i].seconds < 0) {
         ctx.commands().destroy(ents[i]);
         const ecs::Entity e = ctx.commands().create();
         ctx.commands().add(e, Position{});
         ctx.commands().add(e, Lifetime{3});
       }
     }
   }).spawns();
  s.add_each<const Lifetime>("count", [&](const Lifetime&) { seen_by_counter.fetch_add(1); });
  Executor ex(GetParam());
  for (int f = 0; f < 10; ++f) {
    seen_by_counter = 0;
    ex.run(s, w);
    EXPECT_EQ(w.size(), 1000u);
    EXPECT_EQ(seen_by_counter.load(), 1000u) << "the count runs after the sync point";
    EXPECT_EQ(ex.last_frame().commands.dropped, 0u);
  }
  EXPECT_GT(ex.last_frame().commands.created, 0u);
}

TEST_P(ExecutorTest, ChangeDetectionSkipsUntouchedChunks) {
  ecs::World w;
  std::vector<ecs::Entity> ents;
  for (int i = 0; i < 50000; ++i) ents.push_back(w.create_with(Position{}, Velocity{}));
  std::atomic<std::size_t> changed_chunks{0};
  Schedule s;
  s.add_chunks<const Position>("watch",
                               [&](SystemContext& ctx, const ecs::ChunkView<const Position>& c) {
                                 if (c.changed_since<const Position>(ctx.last_run_tick()))
                                   changed_chunks.fetch_add(1);
                               });
  Executor ex(GetParam());
  ex.run(s, w);
  const std::size_t all = ex.last_frame().systems[0].chunks;
  EXPECT_EQ(changed_chunks.load(), all) << "first run: everything is new";
  changed_chunks = 0;
  ex.run(s, w);
  EXPECT_EQ(changed_chunks.load(), 0u) << "nothing written since";
  w.get_mut<Position>(ents[123])->x = 1;
  changed_chunks = 0;
  ex.run(s, w);
  EXPECT_EQ(changed_chunks.load(), 1u) << "one write outside the frame, one chunk";
}

TEST_P(ExecutorTest, ChangesBySystemsEarlierOrLaterInTheFrameAreSeen) {
  ecs::World w;
  for (int i = 0; i < 20000; ++i) w.create_with(Position{}, Velocity{});
  std::atomic<std::size_t> changed{0};
  Schedule s;
  // "watch" runs before "move" in the frame; it must still see move's writes on the next frame.
  s.add_chunks<const Position>("watch",
                               [&](SystemContext& ctx, const ecs::ChunkView<const Position>& c) {
                                 if (c.changed_since<const Position>(ctx.last_run_tick()))
                                   changed.fetch_add(1);
                               });
  s.add_each<Position>("move", [](Position& p) { p.x += 1; });
  Executor ex(GetParam());
  ex.run(s, w);
  for (int f = 0; f < 3; ++f) {
    changed = 0;
    ex.run(s, w);
    EXPECT_EQ(changed.load(), ex.last_frame().systems[0].chunks);
  }
}

TEST_P(ExecutorTest, ReductionIsCombinedInChunkOrder) {
  ecs::World w;
  double expected = 0;
  for (int i = 0; i < 30000; ++i) {
    w.create_with(Position{float(i) * 0.001f, 0, 0});
  }
  // Reference: the same chunk-ordered float sum, computed serially.
  {
    auto q = w.query<const Position>();
    const std::size_t n = q.prepare();
    double total = 0;
    for (std::size_t c = 0; c < n; ++c) {
      double part = 0;
      for (const Position& p : q.chunk(c).get<const Position>()) part += p.x;
      total += part;
    }
    expected = total;
  }
  double got = -1;
  Schedule s;
  s.add_reduce<double, const Position>(
      "sum", 0.0,
      [](const ecs::ChunkView<const Position>& c, double& acc) {
        for (const Position& p : c.get<const Position>()) acc += p.x;
      },
      [](double& a, const double& b) { a += b; },
      [&](SystemContext&, double& total) { got = total; });
  Executor ex(GetParam());
  ex.run(s, w);
  EXPECT_EQ(got, expected);  // bit-identical, not just close
}

TEST_P(ExecutorTest, IndependentSystemsOverlapWhenThreadsAllow) {
  ecs::World w;
  std::atomic<int> inside{0}, max_inside{0};
  // Each system waits (bounded) for the other to be running too.
  const auto patience = std::chrono::milliseconds(GetParam() == 1 ? 20 : 5000);
  auto busy = [&](SystemContext&) {
    const int now = inside.fetch_add(1) + 1;
    int prev = max_inside.load();
    while (prev < now && !max_inside.compare_exchange_weak(prev, now)) {
    }
    const auto until = std::chrono::steady_clock::now() + patience;
    while (max_inside.load() < 2 && std::chrono::steady_clock::now() < until) {
    }
    inside.fetch_sub(1);
  };
  Schedule s;
  s.add_task("a", busy).writes<Position>();
  s.add_task("b", busy).writes<Velocity>();
  Executor ex(GetParam());
  ex.run(s, w);
  EXPECT_EQ(max_inside.load(), GetParam() == 1 ? 1 : 2);
  EXPECT_EQ(ex.last_frame().systems.size(), 2u);
}

// In builds with assertions a system that touches what it did not declare stops the frame with
// AccessViolation naming it (penumbra/ecs/access_check.h).
TEST_P(ExecutorTest, UndeclaredAccessFailsTheFrameLoudly) {
  PENUMBRA_STABILITY("a system touching what it did not declare",
                     "AccessViolation naming the system (builds with assertions)", "-");
  if constexpr (!ecs::kAccessChecks) GTEST_SKIP() << "access checks are compiled out (NDEBUG)";
  ecs::World w;
  w.emplace_resource<Counter>();
  for (int i = 0; i < 1000; ++i) w.create_with(Visited{});
  Schedule writes_what_it_reads;
  writes_what_it_reads
      .add_task("bump", [](SystemContext& ctx) { ++ctx.world().resource<Counter>().value; })
      .reads<Counter>();
  Executor ex(GetParam());
  try {
    ex.run(writes_what_it_reads, w);
    ADD_FAILURE() << "no AccessViolation";
  } catch (const ecs::AccessViolation& v) {
    EXPECT_NE(std::string(v.what()).find("'bump'"), std::string::npos) << v.what();
  }
  EXPECT_EQ(w.resource<Counter>().value, 0);

  Schedule reads_undeclared;  // per chunk, on whichever worker runs it
  reads_undeclared.add_each<Visited>(
      "visit", [&w](Visited& v) { v.count += w.resource<const Counter>().value; });
  EXPECT_THROW(ex.run(reads_undeclared, w), ecs::AccessViolation);
}

// Systems that run at the same time, each with its own parallel_for over entities it looks up in
// the world: no thread runs one system's work under the other's declaration.
TEST_P(ExecutorTest, ConcurrentSystemsWithInnerParallelLoopsPassTheChecks) {
#if defined(PENUMBRA_TSAN)
  GTEST_SKIP() << "a raw tbb::parallel_for inside a system: Debian's libtbb is not instrumented, "
                  "so TSan cannot see its hand-offs (the checked and ASan builds run this test)";
#endif
  ecs::World w;
  std::vector<ecs::Entity> a, b;
  for (int i = 0; i < 2000; ++i) a.push_back(w.create_with(Counter{i}));
  for (int i = 0; i < 2000; ++i) b.push_back(w.create_with(Visited{i}));
  std::vector<int> seen_a(a.size(), -1), seen_b(b.size(), -1);
  // One task per entity: plenty of chances for a waiting thread to steal.
  const auto inner = [](std::size_t n, auto&& body) {
    tbb::parallel_for(std::size_t{0}, n, std::size_t{1}, body, tbb::simple_partitioner());
  };
  Schedule s;
  s.add_task("counters", [&](SystemContext& ctx) {
     inner(a.size(), [&](std::size_t i) { seen_a[i] = ctx.world().get<Counter>(a[i])->value; });
   }).reads<Counter>();
  s.add_task("visits", [&](SystemContext& ctx) {
     inner(b.size(), [&](std::size_t i) { seen_b[i] = ctx.world().get<Visited>(b[i])->count; });
   }).reads<Visited>();
  Executor ex(GetParam());
  for (int f = 0; f < 50; ++f) ASSERT_NO_THROW(ex.run(s, w));
  int bad = 0;
  for (std::size_t i = 0; i < a.size(); ++i) bad += seen_a[i] != static_cast<int>(i);
  for (std::size_t i = 0; i < b.size(); ++i) bad += seen_b[i] != static_cast<int>(i);
  EXPECT_EQ(bad, 0);
}

INSTANTIATE_TEST_SUITE_P(Threads, ExecutorTest, ::testing::Values(1, 2, 8));

}  // namespace
}  // namespace penumbra::jobs
