// Transform component: where an entity sits in the engine's world frame (metres, z up).
#pragma once

#include <glm/mat4x4.hpp>

namespace penumbra::components {

// Object space -> world space, hierarchy already applied (glTF nodes are baked at load).
struct Transform {
  glm::mat4 world{1.0f};
};

}  // namespace penumbra::components
