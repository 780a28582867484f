// libFuzzer target: the height-map JSON sidecar and its application to a small grid
// (heightmap.h: parse_height_sidecar, make_height_field). See README.md.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/load_error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra::assets;
  try {
    const HeightSidecar s =
        parse_height_sidecar({reinterpret_cast<const char*>(data), size}, "fuzz.json");
    const std::vector<float> values = {0, 1, 2, 3, 65535, 7};
    const penumbra::data::HeightField f = make_height_field(3, 2, values, s, "fuzz.pgm");
    if (f.heights.size() != static_cast<std::size_t>(f.width) * f.height) __builtin_trap();
  } catch (const LoadError&) {
  }
  return 0;
}
