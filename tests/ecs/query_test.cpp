#include "penumbra/ecs/query.h"

#include <gtest/gtest.h>

#include <set>

#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {

struct P {
  float x;
};
struct V {
  float x;
};
struct Frozen {};

TEST(Query, IncludeAndExclude) {
  World w;
  std::set<std::uint64_t> expected;
  for (int i = 0; i < 100; ++i) {
    const Entity e = w.create_with(P{float(i)});
    if (i % 2 == 0) w.add(e, V{1.0f});
    if (i % 3 == 0) w.add(e, Frozen{});
    if (i % 2 == 0 && i % 3 != 0) expected.insert(e.bits());
  }
  std::set<std::uint64_t> seen;
  w.query<P, const V>().without<Frozen>().each([&](Entity e, P& p, const V& v) {
    p.x += v.x;
    seen.insert(e.bits());
  });
  EXPECT_EQ(seen, expected);
}

TEST(Query, SeesArchetypesCreatedAfterFirstPrepare) {
  World w;
  auto q = w.query<const P>();
  w.create_with(P{1});
  EXPECT_EQ(q.prepare(), 1u);
  w.create_with(P{2}, V{0});  // new archetype
  EXPECT_EQ(q.prepare(), 2u);
  EXPECT_EQ(q.entity_count(), 2u);
}

TEST(Query, ChunksCoverEveryEntityOnceInStableOrder) {
  World w;
  for (int i = 0; i < 10000; ++i) w.create_with(P{float(i)}, V{float(i)});
  auto q = w.query<const P, const V>();
  const std::size_t n = q.prepare();
  ASSERT_GT(n, 1u);
  std::size_t rows = 0;
  float expect = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const auto view = q.chunk(c);
    EXPECT_EQ(view.ordinal(), c);
    const auto p = view.get<const P>();
    for (std::size_t r = 0; r < view.size(); ++r) EXPECT_EQ(p[r].x, expect++);
    rows += view.size();
  }
  EXPECT_EQ(rows, 10000u);
}

TEST(Query, ChangeDetectionPerChunkAndColumn) {
  World w;
  for (int i = 0; i < 10000; ++i) w.create_with(P{0}, V{0});
  w.set_tick(10);
  auto q = w.query<P, const V>();
  const std::size_t n = q.prepare();
  ASSERT_GE(n, 2u);
  q.chunk(1, 11).get<P>()[0].x = 5;     // write access to chunk 1 only
  (void)q.chunk(0, 11).get<const P>();  // read access stamps nothing
  EXPECT_FALSE(q.chunk(0).changed_since<P>(10));
  EXPECT_TRUE(q.chunk(1).changed_since<P>(10));
  EXPECT_FALSE(q.chunk(1).changed_since<const V>(10)) << "columns are stamped separately";
}

}  // namespace
}  // namespace penumbra::ecs
