// Procedural meshes for the asset tests (sphere fitting, simplification).
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "penumbra/data/mesh.h"

namespace penumbra::assets::test {

// Icosphere of radius 1, outward faces: 20 * 4^levels triangles (5120 at 4).
inline data::MeshData icosphere(int levels) {
  data::MeshData m;
  m.name = "unit_sphere";
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  m.indices = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
               4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
               6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back(0.5f * (m.positions[a] + m.positions[b]));
      return mid[key] = static_cast<std::uint32_t>(m.positions.size() - 1);
    };
    std::vector<std::uint32_t> next;
    for (std::size_t i = 0; i < m.indices.size(); i += 3) {
      const std::uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
      const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    m.indices = std::move(next);
  }
  for (glm::vec3& p : m.positions) p = glm::normalize(p);
  return m;
}

}  // namespace penumbra::assets::test
