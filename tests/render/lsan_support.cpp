// LeakSanitizer and the Vulkan driver and layer, which the Vulkan loader dlopen()s at instance
// creation and dlclose()s at destruction.
//
// Lavapipe (libvulkan_lvp.so, with LLVM) and the validation layer keep some allocations in
// their own global variables for the whole process. Once unloaded, those globals are unmapped:
// LeakSanitizer can no longer see the pointers and reports the blocks as leaks with
// "<unknown module>" frames (measured: 128 bytes after creating and destroying one instance with
// validation, several KiB after rendering). Loading both libraries once more here with
// RTLD_NODELETE keeps them mapped until exit, so their globals stay visible roots and the
// report is free of those false reports; leak checking stays on for everything else.
//
// What remains are real leaks inside the validation layer; lsan.supp (next to this file, read
// at configure time into lsan_suppressions.h) suppresses exactly those, with the reason, as
// LeakSanitizer's built-in default suppressions.
//
// Compiled into every render test executable; does nothing without AddressSanitizer.
#include <dlfcn.h>

#include <initializer_list>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_ASAN 1
#endif

#ifdef PENUMBRA_ASAN
#include "lsan_suppressions.h"

extern "C" const char* __lsan_default_suppressions() {
  return kLsanSuppressions;
}
#endif

namespace {
#ifdef PENUMBRA_ASAN
struct KeepVulkanLibrariesLoaded {
  KeepVulkanLibrariesLoaded() {
    for (const char* lib : {"libvulkan_lvp.so", "libVkLayer_khronos_validation.so"})
      dlopen(lib, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);  // absent elsewhere: nothing to keep
  }
} keep_vulkan_libraries_loaded;
#endif
}  // namespace
