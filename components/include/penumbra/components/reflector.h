// An entity whose sphere set also re-emits the light its surface reflects: each sphere is a
// spherical light ([Guerrero08] sec. 4-5) with the surface sample points made offline by
// systems/spherical_lights (reflector_samples.h: sample_reflector, one entry per sphere of the
// entity's SphereSet, in its order). Needs a Transform; the spherical-light system writes the
// entity's ReflectorRadiance each frame.
#pragma once

#include <memory>

#include "penumbra/data/reflector_samples.h"

namespace penumbra::components {

struct Reflector {
  std::shared_ptr<const data::ReflectorSamples> samples;  // shared, immutable
};

}  // namespace penumbra::components
