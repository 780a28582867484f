// Physical-device choice, as a pure function over a description of each device (testable
// without a GPU).
//
// Automatic choice: among the suitable devices (Vulkan 1.3, a graphics queue that can present
// where a surface is given, the extensions and features the renderer needs), the highest type
// rank wins: discrete > integrated > virtual > CPU (Mesa lavapipe, the software fallback every
// test and CI uses) > other; ties go to the lower index.
//
// Forcing: the string from --device, else the environment variable PENUMBRA_DEVICE, names one:
//   an index ("0"), a type ("discrete", "integrated", "virtual", "cpu"), "lavapipe" or
//   "llvmpipe" (the CPU device), or a case-insensitive substring of the device name.
// A forced device that does not exist or is not suitable is an error (never a silent fallback).
//
// Thread-safe (pure functions; device_preference reads the environment).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <vulkan/vulkan.h>

namespace penumbra::render {

struct DeviceCandidate {
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::uint32_t api_version = 0;
  std::string unsuitable;  // empty: suitable; otherwise why not
};

struct DeviceChoice {
  int index = -1;     // into the candidates; -1 on failure
  std::string error;  // why nothing was chosen (lists the devices)
  bool forced = false;
};

DeviceChoice select_device(std::span<const DeviceCandidate> candidates, std::string_view force);

// `flag` when non-empty, else $PENUMBRA_DEVICE, else "" (automatic).
std::string device_preference(std::string_view flag = {});

const char* device_type_name(VkPhysicalDeviceType type);
// "0: llvmpipe (LLVM 15) [cpu]" lines, with the reason a device is unsuitable.
std::string describe_devices(std::span<const DeviceCandidate> candidates);

}  // namespace penumbra::render
