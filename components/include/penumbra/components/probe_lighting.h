// ProbeLighting: an entity's irradiance SH interpolated from the probe cloud (systems/probe_cloud
// probe_systems.h): what mesh shading and the blocker system read for a dynamic object.
// 4 bands per channel (r, g, b), engine/sh conventions, zero past the cloud's bands.
// Temporal smoothing (ProbeSettingsResource): `irradiance` follows `sample` exponentially and
// starts from the first sample, never from black (godotengine/godot #88101); without smoothing
// both are equal. Written only by probes.walk.
#pragma once

#include "penumbra/sh/basis.h"

namespace penumbra::components {

struct ProbeLighting {
  static constexpr int kBands = 4;
  sh::CoeffsRgb<kBands> irradiance{};  // published (smoothed) irradiance SH
  sh::CoeffsRgb<kBands> sample{};      // this frame's interpolation
  bool valid = false;                  // false until the first sample: nothing to smooth from
};

}  // namespace penumbra::components
