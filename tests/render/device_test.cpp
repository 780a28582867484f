#include "penumbra/render/device.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "common/stability.h"
#include "penumbra/render/resources.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(Device, CreatesTheLavapipeDeviceWithValidation) {
  test::TestContext ctx;
  EXPECT_TRUE(ctx.instance.validation());
  EXPECT_NE(ctx.device.handle(), VK_NULL_HANDLE);
  EXPECT_GE(ctx.device.properties().apiVersion, VK_API_VERSION_1_3);
  EXPECT_FALSE(ctx.device.candidates().empty());
  EXPECT_NE(ctx.device.push_descriptor_fn(), nullptr);
  std::printf("device: %s\n", ctx.device.name().c_str());
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Device, EnvironmentForcesTheCpuDeviceAndRejectsAnUnknownOne) {
  PENUMBRA_STABILITY("PENUMBRA_DEVICE naming an unknown device", "an error naming it", "-");
  Instance instance(test::validated_config());
  ::setenv("PENUMBRA_DEVICE", "lavapipe", 1);
  {
    Device d(instance);
    EXPECT_EQ(d.properties().deviceType, VK_PHYSICAL_DEVICE_TYPE_CPU);
  }
  ::setenv("PENUMBRA_DEVICE", "no-such-gpu", 1);
  try {
    Device d(instance);
    ADD_FAILURE() << "expected an error for an unknown forced device";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpu"), std::string::npos) << e.what();
  }
  ::unsetenv("PENUMBRA_DEVICE");
  DeviceConfig config;
  config.force = "cpu";  // the flag form
  Device d(instance, config);
  EXPECT_EQ(d.properties().deviceType, VK_PHYSICAL_DEVICE_TYPE_CPU);
}

TEST(Device, CountsLiveObjectsAndReturnsToZero) {
  test::TestContext ctx;
  const ObjectCounts before = ctx.device.object_counts();
  {
    Buffer b = create_buffer(ctx.device, 256, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, true);
    ASSERT_NE(b.mapped, nullptr);
    Image i = create_image(
        ctx.device,
        {{8, 8}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT, VK_IMAGE_ASPECT_COLOR_BIT});
    const ObjectCounts during = ctx.device.object_counts();
    EXPECT_EQ(during.live[static_cast<int>(ObjectKind::kBuffer)], 1);
    EXPECT_EQ(during.live[static_cast<int>(ObjectKind::kImage)], 1);
    EXPECT_EQ(during.live[static_cast<int>(ObjectKind::kMemory)], 2);
    EXPECT_EQ(during.total(), before.total() + 5) << during.text();
    Buffer moved = std::move(b);
    EXPECT_EQ(ctx.device.object_counts(), during) << "a move transfers, never duplicates";
  }
  EXPECT_EQ(ctx.device.object_counts(), before) << ctx.device.object_counts().text();
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Device, SubmitAndWaitRunsCommands) {
  test::TestContext ctx;
  Buffer src = create_buffer(ctx.device, 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  Buffer dst = create_buffer(ctx.device, 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  const std::uint32_t words[4] = {1, 2, 3, 0xdeadbeef};
  std::memcpy(src.mapped, words, 16);
  ctx.device.submit_and_wait([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, 16};
    vkCmdCopyBuffer(cmd, src.get(), dst.get(), 1, &region);
  });
  EXPECT_EQ(std::memcmp(dst.mapped, words, 16), 0);
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
