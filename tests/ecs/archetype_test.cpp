#include "penumbra/ecs/archetype.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>

namespace penumbra::ecs {
namespace {

struct Small {
  std::uint32_t v;
};
struct Big {
  char bytes[1024];
};
struct alignas(32) Wide {
  float v[8];
};

TEST(Archetype, ChunkCapacityFollowsRowSize) {
  Archetype small(0, {type_id<Small>()});
  Archetype big(1, {type_id<Big>()});
  EXPECT_EQ(small.chunk_capacity(), Archetype::kMaxRows);
  EXPECT_GE(big.chunk_capacity(), Archetype::kMinRows);
  EXPECT_LT(big.chunk_capacity(), small.chunk_capacity());
  EXPECT_EQ(big.chunk_capacity() % 16, 0u);
}

TEST(Archetype, ColumnsAreAligned) {
  Archetype a(0, {type_id<Small>(), type_id<Wide>()});
  a.push_back(Entity{0, 0}, 1);
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.column(0, c)) % 64, 0u);
  }
  a.swap_remove({0, 0}, /*destroy_components=*/false, 2);
}

TEST(Archetype, SwapRemoveKeepsRowsDenseAcrossChunks) {
  Archetype a(0, {type_id<Small>()});
  const std::uint32_t cap = a.chunk_capacity();
  const std::uint32_t n = cap + 3;
  for (std::uint32_t i = 0; i < n; ++i) {
    const RowRef r = a.push_back(Entity{i, 0}, 1);
    static_cast<Small*>(a.slot(r, 0))->v = i;
  }
  ASSERT_EQ(a.chunk_count(), 2u);
  // Remove row 5 of chunk 0: the archetype's last row (entity n-1) moves in.
  const Entity moved = a.swap_remove({0, 5}, /*destroy_components=*/true, 7);
  EXPECT_EQ(moved.index, n - 1);
  EXPECT_EQ(a.entities(0)[5].index, n - 1);
  EXPECT_EQ(static_cast<Small*>(a.slot({0, 5}, 0))->v, n - 1);
  EXPECT_EQ(a.changed_tick(0, 0), 7u) << "the hole's chunk is stamped";
  EXPECT_EQ(a.size(), n - 1);
  // Empty the second chunk: it is released.
  for (int i = 0; i < 2; ++i) a.swap_remove({1, 0}, true, 8);
  EXPECT_EQ(a.chunk_count(), 1u);
  EXPECT_EQ(a.size(), cap);
  while (a.size() > 0) a.swap_remove({0, 0}, true, 9);
}

TEST(Archetype, DestroysRemainingComponents) {
  auto counter = std::make_shared<int>(0);
  {
    Archetype a(0, {type_id<std::shared_ptr<int>>()});
    for (std::uint32_t i = 0; i < 40; ++i) {
      const RowRef r = a.push_back(Entity{i, 0}, 1);
      ::new (a.slot(r, 0)) std::shared_ptr<int>(counter);
    }
    EXPECT_EQ(counter.use_count(), 41);
    a.swap_remove({0, 3}, true, 2);
    EXPECT_EQ(counter.use_count(), 40);
  }
  EXPECT_EQ(counter.use_count(), 1);
}

}  // namespace
}  // namespace penumbra::ecs
