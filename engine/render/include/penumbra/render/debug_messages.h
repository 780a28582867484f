// DebugMessages: records what the validation layers (VK_EXT_debug_utils) report.
//
// Every warning and error is counted (exactly) and the first kMaxStored are kept with their
// message id and text, so a test can fail on any validation message and say which. Messages
// are optionally echoed to stderr as they arrive.
//
// Threading: the Vulkan loader may call the callback from any thread that makes Vulkan calls;
// record() and every accessor lock an internal mutex.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace penumbra::render {

struct DebugMessage {
  VkDebugUtilsMessageSeverityFlagBitsEXT severity{};
  VkDebugUtilsMessageTypeFlagsEXT type{};
  std::string id;  // e.g. "VUID-VkBufferCreateInfo-size-00912"
  std::string text;
};

class DebugMessages {
 public:
  static constexpr std::size_t kMaxStored = 64;

  explicit DebugMessages(bool echo = true) : echo_(echo) {}

  void record(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT type,
              const char* id, const char* text);
  // The callback to register, with this object as pUserData.
  static VKAPI_ATTR VkBool32 VKAPI_CALL callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT type,
                                                 const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                 void* user);

  std::size_t errors() const;
  std::size_t warnings() const;
  std::size_t total() const;  // errors + warnings
  std::vector<DebugMessage> stored() const;
  // One line per stored message (at most `max`), for test failure output.
  std::string summary(std::size_t max = 8) const;
  void clear();

 private:
  mutable std::mutex mutex_;
  bool echo_;
  std::size_t errors_ = 0, warnings_ = 0;
  std::vector<DebugMessage> stored_;
};

}  // namespace penumbra::render
