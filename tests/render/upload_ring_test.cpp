#include "penumbra/render/upload_ring.h"

#include <gtest/gtest.h>

#include <cstring>

#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(UploadRing, AlignsSlicesAndGrowsIntoOneBlockAtReset) {
  test::TestContext ctx;
  UploadRing ring(ctx.device, 4096);
  const Slice a = ring.upload("abc", 3);
  const Slice b = ring.allocate(100, 256);
  EXPECT_EQ(a.offset, 0u);
  EXPECT_EQ(b.offset % 256, 0u);
  EXPECT_EQ(std::memcmp(a.data, "abc", 3), 0);
  const Slice big = ring.allocate(10000);  // more than the block: a second block
  EXPECT_NE(big.buffer, a.buffer);
  EXPECT_EQ(ring.blocks(), 2u);
  EXPECT_EQ(std::memcmp(a.data, "abc", 3), 0) << "earlier slices stay valid";
  const VkDeviceSize capacity = ring.capacity();
  ring.reset();
  EXPECT_EQ(ring.blocks(), 1u);
  EXPECT_EQ(ring.capacity(), capacity);
  const ObjectCounts counts = ctx.device.object_counts();
  for (int frame = 0; frame < 10; ++frame) {
    ring.allocate(3);
    ring.allocate(10000);
    ring.reset();
  }
  EXPECT_EQ(ctx.device.object_counts(), counts) << "stable once it fits a frame";
}

}  // namespace
}  // namespace penumbra::render
