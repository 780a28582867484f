// A triangle mesh in memory, in its own (object) space.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace penumbra::data {

struct MeshData {
  std::string name;
  std::vector<glm::vec3> positions;  // all finite
  std::vector<glm::vec3> normals;    // empty, or one per position
  std::vector<std::uint32_t> indices;  // triangle list, every index < positions.size()
  glm::vec4 base_color{1, 1, 1, 1};    // linear RGBA (glTF pbrMetallicRoughness.baseColorFactor)
};

}  // namespace penumbra::data
