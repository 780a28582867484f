#include "penumbra/render/debug_messages.h"

#include <cstdio>

namespace penumbra::render {

void DebugMessages::record(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                           VkDebugUtilsMessageTypeFlagsEXT type, const char* id, const char* text) {
  const bool error = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0;
  const bool warning = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) != 0;
  if (!error && !warning) return;
  std::lock_guard lock(mutex_);
  (error ? errors_ : warnings_) += 1;
  if (stored_.size() < kMaxStored)
    stored_.push_back({severity, type, id ? id : "", text ? text : ""});
  if (echo_)
    std::fprintf(stderr, "vulkan %s: [%s] %s\n", error ? "error" : "warning", id ? id : "",
                 text ? text : "");
}

VKAPI_ATTR VkBool32 VKAPI_CALL DebugMessages::callback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT type,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  static_cast<DebugMessages*>(user)->record(severity, type, data ? data->pMessageIdName : nullptr,
                                            data ? data->pMessage : nullptr);
  return VK_FALSE;  // never abort the call
}

std::size_t DebugMessages::errors() const {
  std::lock_guard lock(mutex_);
  return errors_;
}
std::size_t DebugMessages::warnings() const {
  std::lock_guard lock(mutex_);
  return warnings_;
}
std::size_t DebugMessages::total() const {
  std::lock_guard lock(mutex_);
  return errors_ + warnings_;
}
std::vector<DebugMessage> DebugMessages::stored() const {
  std::lock_guard lock(mutex_);
  return stored_;
}

std::string DebugMessages::summary(std::size_t max) const {
  std::lock_guard lock(mutex_);
  std::string out = std::to_string(errors_) + " errors, " + std::to_string(warnings_) + " warnings";
  for (std::size_t i = 0; i < stored_.size() && i < max; ++i)
    out += "\n  [" + stored_[i].id + "] " + stored_[i].text;
  return out;
}

void DebugMessages::clear() {
  std::lock_guard lock(mutex_);
  errors_ = warnings_ = 0;
  stored_.clear();
}

}  // namespace penumbra::render
