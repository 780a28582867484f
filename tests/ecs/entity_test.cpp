#include "penumbra/ecs/entity.h"

#include <gtest/gtest.h>

#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {

TEST(Entity, NullAndPendingAreDistinct) {
  EXPECT_TRUE(kNullEntity.is_null());
  EXPECT_FALSE(kNullEntity.is_pending());
  EXPECT_TRUE((Entity{3, Entity::kPendingGeneration}).is_pending());
  EXPECT_NE((Entity{1, 2}), (Entity{1, 3}));
}

TEST(Entity, DestroyedHandleGoesStale) {
  World w;
  const Entity a = w.create();
  EXPECT_TRUE(w.alive(a));
  EXPECT_TRUE(w.destroy(a));
  EXPECT_FALSE(w.alive(a));
  EXPECT_FALSE(w.destroy(a)) << "destroying a stale handle is a no-op";
}

TEST(Entity, ReusedSlotNeverAliasesStaleHandle) {
  World w;
  const Entity a = w.create();
  w.destroy(a);
  const Entity b = w.create();
  EXPECT_EQ(a.index, b.index) << "slots are reused LIFO";
  EXPECT_NE(a.generation, b.generation);
  EXPECT_FALSE(w.alive(a));
  EXPECT_TRUE(w.alive(b));
  EXPECT_EQ(w.get<int>(a), nullptr);
}

TEST(Entity, NullAndOutOfRangeHandlesAreNotAlive) {
  World w;
  EXPECT_FALSE(w.alive(kNullEntity));
  EXPECT_FALSE(w.alive(Entity{12345, 0}));
  EXPECT_FALSE(w.destroy(Entity{12345, 0}));
}

TEST(Entity, ManyCyclesKeepSlotCountBounded) {
  World w;
  for (int i = 0; i < 10000; ++i) w.destroy(w.create());
  EXPECT_EQ(w.slot_count(), 1u);
  EXPECT_EQ(w.size(), 0u);
}

}  // namespace
}  // namespace penumbra::ecs
