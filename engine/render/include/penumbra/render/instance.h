// Instance: the VkInstance, with the Khronos validation layer and a debug messenger when
// validation is on.
//
// Validation defaults to on in builds with assertions (no NDEBUG: debug and checked presets,
// hence every test) and off in Release; PENUMBRA_VALIDATION=0 or 1 in the environment overrides
// the default. With require_validation, a missing layer is an error (tests must not silently
// run unvalidated); otherwise it is a warning on stderr.
//
// Threading: create and destroy on one thread; handle() may be used from any thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "penumbra/render/debug_messages.h"

namespace penumbra::render {

// The build's default, after the PENUMBRA_VALIDATION override.
bool default_validation();

struct InstanceConfig {
  std::string app_name = "penumbra";
  bool validation = default_validation();
  bool require_validation = false;
  // With validation: also the layer's synchronization validation (missing or wrong barriers;
  // slower, on in tests).
  bool synchronization_validation = false;
  bool echo_messages = true;            // print validation messages to stderr as they arrive
  std::vector<std::string> extensions;  // extra instance extensions (GLFW's surface extensions)
};

class Instance {
 public:
  // Throws VulkanError when no Vulkan loader/driver can create an instance, std::runtime_error
  // when a required layer or extension is missing.
  explicit Instance(const InstanceConfig& config = {});
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance handle() const { return instance_; }
  bool validation() const { return validation_; }
  // Validation messages (empty and unused when validation is off).
  DebugMessages& messages() { return *messages_; }
  const DebugMessages& messages() const { return *messages_; }

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  bool validation_ = false;
  std::unique_ptr<DebugMessages> messages_;  // stable address: the callback's user data
};

}  // namespace penumbra::render
