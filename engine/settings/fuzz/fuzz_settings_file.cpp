// libFuzzer target: the tuned settings file reader (tuned_settings.h). Replayed on the committed
// corpus (corpus/settings_file) by ctest in every build (tests/tune/CMakeLists.txt), with
// engine/assets/fuzz/replay_main.cpp as its main.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "penumbra/assets/load_error.h"
#include "penumbra/settings/tuned_settings.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra::settings;
  try {
    const TunedSettings s =
        parse_settings({reinterpret_cast<const char*>(data), size}, "fuzz.settings");
    // What the reader promises: values in range, and what it read encodes and reads back to the
    // same values.
    if (!(s.budget > 0) || !std::isfinite(s.budget) || s.terrain.azimuths < 3 ||
        s.terrain.bands < 3 || s.terrain.bands > 6 || s.blockers.spheres_per_object < 1 ||
        !(s.blockers.epsilon > 0 && s.blockers.epsilon < 1) || !(s.probes.spacing > 0) ||
        (s.spherical_lights.gather != "receivers" &&
         s.spherical_lights.gather != "clusters_leaves" &&
         s.spherical_lights.gather != "clusters_parents"))
      __builtin_trap();
    if (parse_settings(encode_settings(s), "fuzz.again") != s) __builtin_trap();
  } catch (const penumbra::assets::LoadError&) {
  }
  return 0;
}
