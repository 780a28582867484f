// Mesh components: a reference to shared, immutable triangle data and its base colour.
#pragma once

#include <memory>

#include <glm/vec4.hpp>

namespace penumbra::data {
struct MeshData;  // penumbra/data/mesh.h
}

namespace penumbra::components {

// Many instances share one MeshData; nothing writes through it.
struct MeshInstance {
  std::shared_ptr<const data::MeshData> mesh;
};

// Linear RGBA (glTF pbrMetallicRoughness.baseColorFactor).
struct BaseColor {
  glm::vec4 rgba{1.0f};
};

}  // namespace penumbra::components
