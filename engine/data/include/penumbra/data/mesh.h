// A triangle mesh in memory, in its own (object) space.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace penumbra::data {

struct MeshData {
  std::string name;
  std::vector<glm::vec3> positions;    // all finite
  std::vector<glm::vec3> normals;      // empty, or one per position
  std::vector<std::uint32_t> indices;  // triangle list, every index < positions.size()
  glm::vec4 base_color{1, 1, 1, 1};    // linear RGBA (glTF pbrMetallicRoughness.baseColorFactor)
};

// The mesh's normals, or, when it has none, area-weighted vertex normals (the sum of the
// adjacent triangles' unnormalised normals, normalised; (0, 0, 1) for a vertex with none).
inline std::vector<glm::vec3> vertex_normals(const MeshData& m) {
  if (m.normals.size() == m.positions.size()) return m.normals;
  std::vector<glm::vec3> n(m.positions.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
    const glm::vec3 &a = m.positions[m.indices[i]], &b = m.positions[m.indices[i + 1]],
                    &c = m.positions[m.indices[i + 2]];
    const glm::vec3 f = glm::cross(b - a, c - a);
    for (std::size_t k = 0; k < 3; ++k) n[m.indices[i + k]] += f;
  }
  for (glm::vec3& v : n) {
    const float l = glm::length(v);
    v = l > 0 ? v / l : glm::vec3(0, 0, 1);
  }
  return n;
}

}  // namespace penumbra::data
