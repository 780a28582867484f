// Camera matrices in Vulkan conventions: clip y points down, depth in [0, 1], reversed (near
// plane at depth 1, far plane at depth 0) for precision over long terrain views. The depth
// buffer is cleared to 0 and tested with GREATER; the sky is drawn at depth 0.
//
// Pure functions; thread-safe.
#pragma once

#include <glm/mat4x4.hpp>

#include "penumbra/render/packet.h"

namespace penumbra::render {

// World -> view (right-handed, looking down -z in view space).
glm::mat4 view_matrix(const CameraView& camera);
// View -> clip with reversed depth; aspect = width / height.
glm::mat4 projection_matrix(const CameraView& camera, float aspect);
inline glm::mat4 view_projection(const CameraView& camera, float aspect) {
  return projection_matrix(camera, aspect) * view_matrix(camera);
}

}  // namespace penumbra::render
