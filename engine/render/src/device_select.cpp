#include "penumbra/render/device_select.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace penumbra::render {
namespace {
int rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 1;
    default:
      return 0;
  }
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool matches(const DeviceCandidate& c, int index, const std::string& want) {
  if (!want.empty() && std::all_of(want.begin(), want.end(), [](char ch) {
        return std::isdigit(static_cast<unsigned char>(ch));
      }))
    return std::atoi(want.c_str()) == index;
  if (want == "discrete") return c.type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  if (want == "integrated") return c.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
  if (want == "virtual") return c.type == VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU;
  if (want == "cpu" || want == "lavapipe" || want == "llvmpipe")
    return c.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  return lower(c.name).find(want) != std::string::npos;
}
}  // namespace

const char* device_type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

std::string describe_devices(std::span<const DeviceCandidate> candidates) {
  if (candidates.empty()) return "  (no Vulkan devices: install mesa-vulkan-drivers for lavapipe)";
  std::string out;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const auto& c = candidates[i];
    out += "  " + std::to_string(i) + ": " + c.name + " [" + device_type_name(c.type) + "]";
    if (!c.unsuitable.empty()) out += " unsuitable: " + c.unsuitable;
    out += "\n";
  }
  if (!out.empty()) out.pop_back();
  return out;
}

DeviceChoice select_device(std::span<const DeviceCandidate> candidates, std::string_view force) {
  DeviceChoice choice;
  const std::string want = lower(force);
  choice.forced = !want.empty();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const auto& c = candidates[i];
    const int idx = static_cast<int>(i);
    if (choice.forced) {
      if (!matches(c, idx, want)) continue;
      if (!c.unsuitable.empty()) {
        // Appended piecewise: "literal" + std::string&& trips a GCC 12 -Wrestrict false positive.
        choice.error = "device '";
        choice.error.append(force).append("' (").append(c.name).append(") is not suitable: ");
        choice.error.append(c.unsuitable).append("\n").append(describe_devices(candidates));
        return choice;
      }
      choice.index = idx;
      return choice;
    }
    if (!c.unsuitable.empty()) continue;
    if (choice.index < 0 || rank(c.type) > rank(candidates[choice.index].type)) choice.index = idx;
  }
  if (choice.index < 0) {
    if (choice.forced) {
      choice.error = "no Vulkan device matches '";
      choice.error.append(force).append("'");
    } else {
      choice.error = "no suitable Vulkan device";
    }
    choice.error.append("\n").append(describe_devices(candidates));
  }
  return choice;
}

std::string device_preference(std::string_view flag) {
  if (!flag.empty()) return std::string(flag);
  const char* env = std::getenv("PENUMBRA_DEVICE");
  return env ? env : "";
}

}  // namespace penumbra::render
