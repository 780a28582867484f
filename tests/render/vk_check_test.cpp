#include "penumbra/render/vk_check.h"

#include <gtest/gtest.h>

#include <string>
#include "common/stability.h"

namespace penumbra::render {
namespace {

TEST(VkCheck, ErrorsNameTheCallAndTheResult) {
  PENUMBRA_STABILITY("a failed Vulkan call", "VulkanError naming the call and the result", "-");
  EXPECT_NO_THROW(vk_check(VK_SUCCESS, "vkCreateDevice"));
  try {
    vk_check(VK_ERROR_FEATURE_NOT_PRESENT, "vkCreateDevice");
    ADD_FAILURE() << "expected a VulkanError";
  } catch (const VulkanError& e) {
    EXPECT_EQ(std::string(e.what()), "vkCreateDevice: VK_ERROR_FEATURE_NOT_PRESENT");
    EXPECT_EQ(e.result(), VK_ERROR_FEATURE_NOT_PRESENT);
  }
  EXPECT_STREQ(VulkanError::result_name(VK_ERROR_OUT_OF_DATE_KHR), "VK_ERROR_OUT_OF_DATE_KHR");
  EXPECT_STREQ(VulkanError::result_name(static_cast<VkResult>(-12345)), "VkResult(unknown)");
}

TEST(VkCheck, StructsAreZeroedWithTheirType) {
  const auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  EXPECT_EQ(info.sType, VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  EXPECT_EQ(info.pNext, nullptr);
  EXPECT_EQ(info.size, 0u);
}

}  // namespace
}  // namespace penumbra::render
