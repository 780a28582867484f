// The distant environment light, a world resource: an HDR map and its SH projection.
// Writers (the environment stage, the demo) bump `version` when the map or its SH change;
// rotating the sky only changes rotation_z (readers re-shade from stored transfer vectors).
#pragma once

#include <cstdint>
#include <memory>

#include "penumbra/sh/basis.h"

namespace penumbra::data {
struct EnvironmentMap;  // penumbra/data/environment_map.h
}

namespace penumbra::components {

struct EnvironmentLight {
  std::shared_ptr<const data::EnvironmentMap> map;  // may be null when only SH is known
  sh::CoeffsRgb<sh::kDefaultBands> radiance{};        // SH of the map's radiance, unrotated
  float rotation_z = 0;  // radians, counter-clockwise about +z (the map's world orientation)
  std::uint64_t version = 0;
};

}  // namespace penumbra::components
