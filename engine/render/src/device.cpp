#include "penumbra/render/device.h"

#include <cstring>
#include <stdexcept>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
struct Probe {
  DeviceCandidate candidate;
  std::uint32_t queue_family = 0;
  bool large_points = false;
  bool timestamps = false;
};

bool has_device_extension(VkPhysicalDevice pd, const char* name) {
  std::uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

Probe probe(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  Probe p;
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(pd, &props);
  p.candidate.name = props.deviceName;
  p.candidate.type = props.deviceType;
  p.candidate.api_version = props.apiVersion;
  std::string& why = p.candidate.unsuitable;
  auto fail = [&](const std::string& reason) { why += (why.empty() ? "" : "; ") + reason; };

  if (props.apiVersion < VK_API_VERSION_1_3) fail("Vulkan < 1.3");
  VkPhysicalDeviceVulkan13Features f13 = vk_struct<VkPhysicalDeviceVulkan13Features>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  VkPhysicalDeviceFeatures2 f2 =
      vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  f2.pNext = &f13;
  if (props.apiVersion >= VK_API_VERSION_1_3) {
    vkGetPhysicalDeviceFeatures2(pd, &f2);
    if (!f13.dynamicRendering) fail("no dynamicRendering");
    if (!f13.synchronization2) fail("no synchronization2");
  }
  p.large_points = f2.features.largePoints == VK_TRUE;
  if (!has_device_extension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
    fail("no VK_KHR_push_descriptor");
  if (surface != VK_NULL_HANDLE && !has_device_extension(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
    fail("no VK_KHR_swapchain");

  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  bool found = false;
  for (std::uint32_t i = 0; i < n && !found; ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) continue;
    if (surface != VK_NULL_HANDLE) {
      VkBool32 present = VK_FALSE;
      vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, surface, &present);
      if (!present) continue;
    }
    found = true;
    p.queue_family = i;
    p.timestamps = families[i].timestampValidBits > 0 && props.limits.timestampPeriod > 0;
  }
  if (!found) fail(surface ? "no graphics queue that presents to the window" : "no graphics queue");
  return p;
}
}  // namespace

const char* object_kind_name(ObjectKind kind) {
  static constexpr const char* kNames[] = {
      "buffer",      "image",           "image_view", "memory",          "sampler",
      "pipeline",    "pipeline_layout", "set_layout", "shader_module",   "semaphore",
      "fence",       "command_pool",    "query_pool", "descriptor_pool", "render_pass",
      "framebuffer", "swapchain"};
  static_assert(std::size(kNames) == static_cast<std::size_t>(ObjectKind::kCount));
  return kNames[static_cast<int>(kind)];
}

std::int64_t ObjectCounts::total() const {
  std::int64_t t = 0;
  for (auto v : live) t += v;
  return t;
}

std::string ObjectCounts::text() const {
  std::string out;
  for (int k = 0; k < static_cast<int>(ObjectKind::kCount); ++k) {
    if (live[k] == 0) continue;
    if (!out.empty()) out += ", ";
    out +=
        std::string(object_kind_name(static_cast<ObjectKind>(k))) + " " + std::to_string(live[k]);
  }
  return out.empty() ? "none" : out;
}

Device::Device(Instance& instance, const DeviceConfig& config) : instance_(&instance) {
  std::uint32_t n = 0;
  const VkResult r = vkEnumeratePhysicalDevices(instance.handle(), &n, nullptr);
  if (r != VK_SUCCESS && r != VK_INCOMPLETE) throw VulkanError("vkEnumeratePhysicalDevices", r);
  std::vector<VkPhysicalDevice> devices(n);
  vkEnumeratePhysicalDevices(instance.handle(), &n, devices.data());
  std::vector<Probe> probes;
  for (VkPhysicalDevice pd : devices) {
    probes.push_back(probe(pd, config.present_surface));
    candidates_.push_back(probes.back().candidate);
  }
  const DeviceChoice choice = select_device(candidates_, device_preference(config.force));
  if (choice.index < 0) throw std::runtime_error("Vulkan device selection: " + choice.error);
  const Probe& chosen = probes[choice.index];
  physical_ = devices[choice.index];
  queue_family_ = chosen.queue_family;
  large_points_ = chosen.large_points;
  timestamps_ = chosen.timestamps;
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue =
      vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  std::vector<const char*> extensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  if (config.present_surface != VK_NULL_HANDLE)
    extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  VkPhysicalDeviceVulkan13Features f13 = vk_struct<VkPhysicalDeviceVulkan13Features>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  f13.dynamicRendering = VK_TRUE;
  f13.synchronization2 = VK_TRUE;
  VkPhysicalDeviceFeatures2 f2 =
      vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  f2.pNext = &f13;
  f2.features.largePoints = large_points_ ? VK_TRUE : VK_FALSE;
  VkDeviceCreateInfo info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.pNext = &f2;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  vk_check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  push_descriptor_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));

  VkCommandPoolCreateInfo pool =
      vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool.queueFamilyIndex = queue_family_;
  const VkResult pr = vkCreateCommandPool(device_, &pool, nullptr, &upload_pool_);
  if (pr != VK_SUCCESS) {
    vkDestroyDevice(device_, nullptr);
    throw VulkanError("vkCreateCommandPool", pr);
  }
}

Device::~Device() {
  if (device_ == VK_NULL_HANDLE) return;
  vkDeviceWaitIdle(device_);
  vkDestroyCommandPool(device_, upload_pool_, nullptr);
  vkDestroyDevice(device_, nullptr);
}

std::uint32_t Device::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                  VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags flags = memory_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  if (fallback < 0) throw std::runtime_error("no Vulkan memory type with the required flags");
  return static_cast<std::uint32_t>(fallback);
}

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo alloc =
      vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = upload_pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  vk_check(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
  VkFence fence = VK_NULL_HANDLE;
  try {
    VkCommandBufferBeginInfo begin =
        vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk_check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    record(cmd);
    vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkFenceCreateInfo fi = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    vk_check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    vk_check(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
    vk_check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  } catch (...) {
    vkDeviceWaitIdle(device_);
    if (fence) vkDestroyFence(device_, fence, nullptr);
    vkFreeCommandBuffers(device_, upload_pool_, 1, &cmd);
    throw;
  }
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, upload_pool_, 1, &cmd);
}

void Device::wait_idle() const {
  vk_check(vkDeviceWaitIdle(device_), "vkDeviceWaitIdle");
}

ObjectCounts Device::object_counts() const {
  ObjectCounts c;
  for (std::size_t i = 0; i < c.live.size(); ++i) c.live[i] = live_[i].load();
  return c;
}

}  // namespace penumbra::render
