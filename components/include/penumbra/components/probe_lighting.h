// ProbeLighting: an entity's irradiance SH interpolated from the probe cloud (systems/probe_cloud
// probe_systems.h): what mesh shading and the blocker system read for a dynamic object.
// 3 bands per channel (r, g, b), engine/sh conventions: the cloud's default. A 2-band cloud
// leaves band 2 zero; a 4-band cloud's band 3 is not kept: irradiance is radiance convolved with
// the clamped cosine, whose l = 3 coefficient is 0 ([Ramamoorthi01]), so that band holds only
// the projection's noise (docs/probe_cloud.md: 4 bands give the same error as 3).
// Temporal smoothing (ProbeSettingsResource): `irradiance` follows each frame's interpolation
// exponentially, blended in place (no second copy is kept), and starts from the first sample,
// never from black (godotengine/godot #88101); without smoothing it is the interpolation.
// 112 bytes (was 388 with 4 bands and the unsmoothed sample beside it). Written only by
// probes.walk.
#pragma once

#include "penumbra/sh/basis.h"

namespace penumbra::components {

struct ProbeLighting {
  static constexpr int kBands = 3;
  sh::CoeffsRgb<kBands> irradiance{};  // published (smoothed) irradiance SH
  bool valid = false;                  // false until the first sample: nothing to smooth from
};

}  // namespace penumbra::components
