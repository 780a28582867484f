#include "penumbra/render/gpu_timer.h"

#include <gtest/gtest.h>

#include <sstream>

#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(GpuTimer, TimesBracketedCommands) {
  test::TestContext ctx;
  ASSERT_TRUE(ctx.device.timestamps()) << "lavapipe supports timestamps";
  GpuTimer timer(ctx.device);
  Buffer a = create_buffer(ctx.device, 1 << 20, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  Buffer b = create_buffer(ctx.device, 1 << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  ctx.device.submit_and_wait([&](VkCommandBuffer cmd) {
    timer.start(cmd);
    const VkBufferCopy region{0, 0, 1 << 20};
    vkCmdCopyBuffer(cmd, a.get(), b.get(), 1, &region);
    timer.mark(cmd, "copy");
    timer.mark(cmd, "nothing");
  });
  const std::vector<PassTime> t = timer.read();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_STREQ(t[0].name, "copy");
  EXPECT_GT(t[0].ms, 0.0);
  EXPECT_GE(t[1].ms, 0.0);
  EXPECT_TRUE(timer.read().empty()) << "read() consumes the frame's record";
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(PassTimingTable, AveragesPerPassInFirstSeenOrder) {
  PassTimingTable table;
  const PassTime f1[] = {{"terrain", 2.0}, {"sky", 1.0}};
  const PassTime f2[] = {{"terrain", 4.0}, {"sky", 1.0}, {"overlay", 0.5}};
  table.add(f1);
  table.add(f2);
  EXPECT_EQ(table.frames(), 2u);
  ASSERT_EQ(table.rows().size(), 3u);
  EXPECT_EQ(table.rows()[0].name, "terrain");
  EXPECT_DOUBLE_EQ(table.mean_ms("terrain"), 3.0);
  EXPECT_DOUBLE_EQ(table.rows()[0].max_ms, 4.0);
  EXPECT_DOUBLE_EQ(table.mean_total_ms(), 4.25);
  std::ostringstream text;
  table.print(text);
  EXPECT_NE(text.str().find("overlay"), std::string::npos);
  EXPECT_NE(text.str().find("GPU frame"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::render
