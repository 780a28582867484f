// Small closed meshes for the spherical-light tests.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "penumbra/data/mesh.h"

namespace penumbra::spherical_lights::test {

// Axis-aligned box [lo, hi], 12 triangles, outward winding, 4 vertices per face with the face's
// normal (flat shading: no smoothing across edges).
inline data::MeshData box_mesh(glm::vec3 lo, glm::vec3 hi, glm::vec3 colour = glm::vec3(1.0f)) {
  data::MeshData m;
  m.name = "box";
  auto corner = [&](int i) {
    return glm::vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
  };
  // Each face counter-clockwise seen from outside, with its outward normal.
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const glm::vec3 normal[6] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};
  for (int f = 0; f < 6; ++f) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int k = 0; k < 4; ++k)
      m.positions.push_back(corner(q[f][k])), m.normals.push_back(normal[f]);
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
  }
  m.base_color = glm::vec4(colour, 1.0f);
  return m;
}

}  // namespace penumbra::spherical_lights::test
