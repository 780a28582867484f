// What the blocker tests share: the unit tests' band count, and the environment maps the
// accuracy tests use against the reference integrator.
#pragma once

#include <cstddef>

#include "penumbra/data/environment_map.h"

namespace penumbra::blocker_accumulation {

// The band count the unit tests run at (one definition, so that a unity build sees one).
inline constexpr int N = 4;

}  // namespace penumbra::blocker_accumulation

namespace penumbra::blocker_accumulation::test {

// Radiance 1 in every direction (64 x 32 equirectangular): open-sky irradiance pi.
inline data::EnvironmentMap uniform_sky() {
  data::EnvironmentMap m;
  m.width = 64;
  m.height = 32;
  m.rgb.assign(static_cast<std::size_t>(m.width) * m.height * 3, 1.0f);
  m.source = "uniform";
  return m;
}

}  // namespace penumbra::blocker_accumulation::test
