// libFuzzer target: the P5 PGM parser (heightmap.h). See README.md.
#include <cstddef>
#include <cstdint>

#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/load_error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const penumbra::assets::PgmImage img = penumbra::assets::parse_pgm({data, size}, "fuzz.pgm");
    if (img.samples.size() != static_cast<std::size_t>(img.width) * img.height) __builtin_trap();
  } catch (const penumbra::assets::LoadError&) {
  }
  return 0;
}
