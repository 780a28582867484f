#include "penumbra/render/device_select.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>
#include "common/stability.h"

namespace penumbra::render {
namespace {

std::vector<DeviceCandidate> machine() {
  return {
      {"llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU, VK_API_VERSION_1_3, ""},
      {"Intel(R) UHD Graphics 630", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU, VK_API_VERSION_1_3, ""},
      {"NVIDIA GeForce RTX 3070", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_API_VERSION_1_3, ""}};
}

TEST(DeviceSelect, PrefersDiscreteThenIntegratedThenCpu) {
  auto devices = machine();
  EXPECT_EQ(select_device(devices, "").index, 2);
  devices[2].unsuitable = "Vulkan < 1.3";
  EXPECT_EQ(select_device(devices, "").index, 1);
  devices[1].unsuitable = "no VK_KHR_push_descriptor";
  const DeviceChoice c = select_device(devices, "");
  EXPECT_EQ(c.index, 0) << "falls back to lavapipe";
  EXPECT_FALSE(c.forced);
}

TEST(DeviceSelect, ForcingByTypeNameIndexAndSubstring) {
  const auto devices = machine();
  EXPECT_EQ(select_device(devices, "lavapipe").index, 0);
  EXPECT_EQ(select_device(devices, "llvmpipe").index, 0);
  EXPECT_EQ(select_device(devices, "cpu").index, 0);
  EXPECT_EQ(select_device(devices, "integrated").index, 1);
  EXPECT_EQ(select_device(devices, "Discrete").index, 2);
  EXPECT_EQ(select_device(devices, "1").index, 1);
  EXPECT_EQ(select_device(devices, "rtx").index, 2);
  EXPECT_TRUE(select_device(devices, "rtx").forced);
}

TEST(DeviceSelect, ForcedDeviceMissingOrUnsuitableIsAnErrorNotAFallback) {
  PENUMBRA_STABILITY("a forced device that is missing or below Vulkan 1.3",
                     "an error listing the devices, no fallback", "-");
  auto devices = machine();
  DeviceChoice c = select_device(devices, "radeon");
  EXPECT_EQ(c.index, -1);
  EXPECT_NE(c.error.find("radeon"), std::string::npos);
  EXPECT_NE(c.error.find("llvmpipe"), std::string::npos) << "lists the devices: " << c.error;
  devices[2].unsuitable = "Vulkan < 1.3";
  c = select_device(devices, "discrete");
  EXPECT_EQ(c.index, -1);
  EXPECT_NE(c.error.find("Vulkan < 1.3"), std::string::npos) << c.error;
  EXPECT_EQ(select_device(devices, "7").index, -1);
}

TEST(DeviceSelect, NoDevicesExplainsWhatToInstall) {
  const DeviceChoice c = select_device({}, "");
  EXPECT_EQ(c.index, -1);
  EXPECT_NE(c.error.find("mesa-vulkan-drivers"), std::string::npos) << c.error;
}

TEST(DeviceSelect, PreferenceFlagOverridesEnvironment) {
  ::setenv("PENUMBRA_DEVICE", "cpu", 1);
  EXPECT_EQ(device_preference(""), "cpu");
  EXPECT_EQ(device_preference("discrete"), "discrete");
  ::unsetenv("PENUMBRA_DEVICE");
  EXPECT_EQ(device_preference(""), "");
}

}  // namespace
}  // namespace penumbra::render
