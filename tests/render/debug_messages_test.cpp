#include "penumbra/render/debug_messages.h"

#include <gtest/gtest.h>

#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(DebugMessages, CountsWarningsAndErrorsAndIgnoresInfo) {
  DebugMessages m(/*echo=*/false);
  m.record(VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT, 0, "info", "ignored");
  m.record(VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT, 0, "W-1", "a warning");
  m.record(VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT, 0, "E-1", "an error");
  EXPECT_EQ(m.warnings(), 1u);
  EXPECT_EQ(m.errors(), 1u);
  EXPECT_EQ(m.total(), 2u);
  EXPECT_NE(m.summary().find("[E-1] an error"), std::string::npos) << m.summary();
  m.clear();
  EXPECT_EQ(m.total(), 0u);
}

TEST(DebugMessages, KeepsCountingPastTheStoredMessages) {
  DebugMessages m(false);
  for (std::size_t i = 0; i < DebugMessages::kMaxStored + 10; ++i)
    m.record(VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT, 0, "E", "x");
  EXPECT_EQ(m.errors(), DebugMessages::kMaxStored + 10);
  EXPECT_EQ(m.stored().size(), DebugMessages::kMaxStored);
}

// The messenger is live: an invalid call (a zero-sized buffer) is reported with its VUID.
TEST(DebugMessages, ValidationLayerReportsAnInvalidCall) {
  InstanceConfig config = test::validated_config();
  config.echo_messages = false;
  Instance instance(config);
  Device device(instance);
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = 0;  // VUID-VkBufferCreateInfo-size-00912
  info.usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  vkCreateBuffer(device.handle(), &info, nullptr, &buffer);
  if (buffer != VK_NULL_HANDLE) vkDestroyBuffer(device.handle(), buffer, nullptr);
  ASSERT_GE(instance.messages().errors(), 1u);
  EXPECT_NE(instance.messages().summary().find("VkBufferCreateInfo-size"), std::string::npos)
      << instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
