// Test helper: small, consistent probe clouds built by hand (no tetrahedralizer), for the cloud
// file's tests and the seed corpus of fuzz_probe_cloud_file (engine/assets/fuzz/corpus/).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/probe_cloud.h"

namespace penumbra::assets::test {

// The coefficients of det[p0 + t n0 - p, p1 + t n1 - p, p2 + t n2 - p] in t^3, t^2, t, 1 for
// a hull triangle (p_i, n_i) at the point p ([Cupisz12]); each is affine in p.
inline glm::dvec4 outer_cubic(const glm::dvec3 p[3], const glm::dvec3 n[3], glm::dvec3 x) {
  const auto det = [](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    return glm::dot(a, glm::cross(b, c));
  };
  const glm::dvec3 a0 = p[0] - x, a1 = p[1] - x, a2 = p[2] - x;
  return {det(n[0], n[1], n[2]), det(a0, n[1], n[2]) + det(n[0], a1, n[2]) + det(n[0], n[1], a2),
          det(a0, a1, n[2]) + det(a0, n[1], a2) + det(n[0], a1, a2), det(a0, a1, a2)};
}

// One positively oriented tetrahedron (the unit corner: origin, e_x, e_y, e_z), its four
// outer cells with symmetric links, unit outward hull normals (the normalized sum of the
// incident face normals), the cells' transforms as data/probe_cloud.h defines them, and a
// smooth SH per probe (coefficient i of channel c of probe k: 0.1 (k + 1) (c + 1) / (i + 1)).
inline data::ProbeCloud single_tetrahedron_cloud(int bands = data::kProbeDefaultBands) {
  data::ProbeCloud c;
  c.bands = bands;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (std::size_t k = 0; k < 4; ++k)
    for (int ch = 0; ch < 3; ++ch)
      for (int i = 0; i < bands * bands; ++i)
        c.sh.push_back(0.1f * static_cast<float>((k + 1) * static_cast<std::size_t>(ch + 1)) /
                       static_cast<float>(i + 1));
  // Cell 0 the tetrahedron; 1..4 the outer cells on the faces opposite its vertices 0..3, each
  // ordered so that (p1 - p0) x (p2 - p0) points out of the hull.
  c.cells = {{{0, 1, 2, 3}, {1, 2, 3, 4}},
             {{1, 2, 3, data::kOuterVertex}, {2, 3, 4, 0}},
             {{0, 3, 2, data::kOuterVertex}, {1, 4, 3, 0}},
             {{0, 1, 3, data::kOuterVertex}, {1, 2, 4, 0}},
             {{0, 2, 1, data::kOuterVertex}, {1, 3, 2, 0}}};
  c.inner_count = 1;
  std::vector<glm::dvec3> normal_sum(4, glm::dvec3(0));
  for (std::size_t i = 1; i < c.cells.size(); ++i) {
    const auto& v = c.cells[i].vertices;
    const glm::dvec3 p0 = c.positions[static_cast<std::size_t>(v[0])];
    const glm::dvec3 face =
        glm::normalize(glm::cross(glm::dvec3(c.positions[static_cast<std::size_t>(v[1])]) - p0,
                                  glm::dvec3(c.positions[static_cast<std::size_t>(v[2])]) - p0));
    for (int k = 0; k < 3; ++k)
      normal_sum[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])] += face;
  }
  for (const glm::dvec3& s : normal_sum) c.hull_normals.push_back(glm::vec3(glm::normalize(s)));
  for (const data::ProbeCell& cell : c.cells) {
    const auto pos = [&](int k) {
      return glm::dvec3(
          c.positions[static_cast<std::size_t>(cell.vertices[static_cast<std::size_t>(k)])]);
    };
    if (!cell.outer()) {
      const glm::dvec3 p3 = pos(3);
      const glm::dmat3 t_inv = glm::inverse(glm::dmat3(pos(0) - p3, pos(1) - p3, pos(2) - p3));
      glm::mat4 m = glm::mat4(glm::mat3(t_inv));
      m[3] = glm::vec4(glm::vec3(p3), 1.0f);
      c.transforms.push_back(m);
      continue;
    }
    glm::dvec3 p[3], n[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = pos(k);
      n[k] = c.hull_normals[static_cast<std::size_t>(cell.vertices[static_cast<std::size_t>(k)])];
    }
    // Row k dotted with (x, 1) is the coefficient of t^(3-k): the affine map from its values
    // at the origin and the unit vectors.
    const glm::dvec4 at0 = outer_cubic(p, n, glm::dvec3(0));
    glm::mat4 m(0.0f);
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 e(0);
      e[axis] = 1;
      m[axis] = glm::vec4(outer_cubic(p, n, e) - at0);
    }
    m[3] = glm::vec4(at0);
    c.transforms.push_back(m);
  }
  return c;
}

}  // namespace penumbra::assets::test
