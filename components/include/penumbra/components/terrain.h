// Terrain component: a height field placed in the world, and its albedo.
// The heights are shared and immutable: an edit publishes a new HeightField.
#pragma once

#include <memory>

#include <glm/vec3.hpp>

namespace penumbra::assets {
struct HeightField;  // penumbra/assets/height_field.h
}

namespace penumbra::components {

struct TerrainSurface {
  std::shared_ptr<const assets::HeightField> heights;
  glm::vec3 origin{0.0f};  // world position of sample (0, 0) at height 0
  glm::vec3 albedo{0.5f};  // linear
};

}  // namespace penumbra::components
