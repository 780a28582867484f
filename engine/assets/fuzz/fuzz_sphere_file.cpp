// libFuzzer target: the sphere set file reader (sphere_file.h). See README.md.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "penumbra/assets/load_error.h"
#include "penumbra/assets/sphere_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra::assets;
  try {
    const SphereSetFile set = parse_sphere_file({data, size}, "fuzz.psph");
    // What the reader promises: finite values, radii >= 0, parents in range, and the bytes
    // re-encode to the very input.
    const auto n = static_cast<std::int64_t>(set.spheres.size());
    for (const auto& s : set.spheres) {
      if (!std::isfinite(s.centre.x) || !std::isfinite(s.centre.y) || !std::isfinite(s.centre.z) ||
          !(s.radius >= 0) || !std::isfinite(s.radius) || s.parent < -1 || s.parent >= n)
        __builtin_trap();
    }
    if (!std::isfinite(set.outside_volume_ratio) || !(set.coverage >= 0 && set.coverage <= 1))
      __builtin_trap();
    const auto again = encode_sphere_file(set);
    if (again.size() != size) __builtin_trap();
    for (std::size_t i = 0; i < size; ++i)
      if (again[i] != data[i]) __builtin_trap();
  } catch (const LoadError&) {
  }
  return 0;
}
