// Vulkan error handling: every failing call becomes a VulkanError naming the call and the
// VkResult, so a test or the main job reports "vkCreateDevice: VK_ERROR_FEATURE_NOT_PRESENT"
// instead of a bare number.
//
// Thread-safe (no state).
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace penumbra::render {

class VulkanError : public std::runtime_error {
 public:
  VulkanError(const std::string& what, VkResult result)
      : std::runtime_error(what + ": " + result_name(result)), result_(result) {}
  VkResult result() const { return result_; }
  static const char* result_name(VkResult r);

 private:
  VkResult result_;
};

// A zero-initialised Vulkan struct with its sType set. (`VkFooInfo info{VK_STRUCTURE_TYPE_...}`
// trips -Wmissing-field-initializers.)
template <class T>
T vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

// Throws VulkanError(what, r) unless r is VK_SUCCESS.
inline void vk_check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw VulkanError(what, r);
}

}  // namespace penumbra::render
