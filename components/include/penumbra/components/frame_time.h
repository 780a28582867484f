// Resource: the frame clock every system reads.
#pragma once

#include <cstdint>

namespace penumbra::components {

struct FrameTime {
  float dt = 1.0f / 60.0f;  // seconds simulated by this frame
  double elapsed = 0;       // seconds since start
  std::uint64_t frame = 0;
};

}  // namespace penumbra::components
