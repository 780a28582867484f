// What the spherical-light system computed for a Reflector this frame ([Guerrero08] eq. 11):
// per spherical light, its radiance L^c as 4-band RGB SH in the entity's local frame.
// Published as a shared immutable array, replaced rather than changed.
#pragma once

#include <memory>
#include <vector>

#include "penumbra/sh/basis.h"

namespace penumbra::components {

struct ReflectorRadiance {
  static constexpr int kBands = 4;
  std::shared_ptr<const std::vector<sh::CoeffsRgb<kBands>>> radiance;  // one per sphere
};

}  // namespace penumbra::components
