#include "penumbra/render/instance.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool has_layer(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

// `layer`: nullptr for the loader's and drivers' extensions, or a layer's own.
bool has_extension(const char* name, const char* layer = nullptr) {
  std::uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(DebugMessages* messages) {
  VkDebugUtilsMessengerCreateInfoEXT info = vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = &DebugMessages::callback;
  info.pUserData = messages;
  return info;
}
}  // namespace

bool default_validation() {
  if (const char* v = std::getenv("PENUMBRA_VALIDATION"); v != nullptr && *v != '\0')
    return std::strcmp(v, "0") != 0;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

Instance::Instance(const InstanceConfig& config)
    : messages_(std::make_unique<DebugMessages>(config.echo_messages)) {
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  bool sync_validation = false;
  for (const auto& e : config.extensions) extensions.push_back(e.c_str());
  if (config.validation) {
    const bool layer = has_layer(kValidationLayer);
    const bool utils =
        has_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME) ||
        (layer && has_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME, kValidationLayer));
    if (layer && utils) {
      layers.push_back(kValidationLayer);
      extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
      validation_ = true;
      sync_validation = config.synchronization_validation &&
                        has_extension(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME, kValidationLayer);
      if (sync_validation) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    } else if (config.require_validation) {
      throw std::runtime_error(std::string("validation required but ") +
                               (layer ? VK_EXT_DEBUG_UTILS_EXTENSION_NAME : kValidationLayer) +
                               " is not available (Debian: vulkan-validationlayers)");
    } else {
      std::fprintf(stderr, "penumbra: %s not available, running without validation\n",
                   kValidationLayer);
    }
  }
  for (const char* e : extensions)
    if (!has_extension(e) && !(validation_ && has_extension(e, kValidationLayer)))
      throw std::runtime_error(std::string("Vulkan instance extension missing: ") + e);

  VkApplicationInfo app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = config.app_name.c_str();
  app.pEngineName = "penumbra";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo info =
      vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  // Chained so that vkCreateInstance / vkDestroyInstance are validated too.
  VkDebugUtilsMessengerCreateInfoEXT chained = messenger_info(messages_.get());
  const VkValidationFeatureEnableEXT sync =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features =
      vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  if (validation_) {
    info.pNext = &chained;
    if (sync_validation) chained.pNext = &features;
  }
  vk_check(vkCreateInstance(&info, nullptr, &instance_), "vkCreateInstance");

  if (validation_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    const VkDebugUtilsMessengerCreateInfoEXT m = messenger_info(messages_.get());
    const VkResult r =
        create ? create(instance_, &m, nullptr, &messenger_) : VK_ERROR_EXTENSION_NOT_PRESENT;
    if (r != VK_SUCCESS) {
      vkDestroyInstance(instance_, nullptr);
      throw VulkanError("vkCreateDebugUtilsMessengerEXT", r);
    }
  }
}

Instance::~Instance() {
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

}  // namespace penumbra::render
