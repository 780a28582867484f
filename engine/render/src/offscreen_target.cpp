#include "penumbra/render/offscreen_target.h"

namespace penumbra::render {

OffscreenTarget::OffscreenTarget(std::uint32_t width, std::uint32_t height)
    : extent_{width, height} {}

std::optional<TargetFrame> OffscreenTarget::acquire(std::uint32_t) {
  if (extent_.width == 0 || extent_.height == 0) return std::nullopt;
  return TargetFrame{};
}

}  // namespace penumbra::render
