// A probe cloud: irradiance probes at points in space, their Delaunay tetrahedralization and the
// outer cells past its hull ([Sukys14] sec. 3.2 and 4.2, [Cupisz12]). Plain data shared by the
// tetrahedralizer and the walk (systems/probe_cloud), the cloud file (engine/assets
// probe_cloud_file.h) and, later, the baker. No behaviour here beyond index arithmetic.
// Threading: a plain value type; the traversal system shares one immutable cloud between threads.
//
// Cells. A cloud with at least 4 affinely independent probes has two kinds of cell:
//  - inner tetrahedra (vertices[3] >= 0): four probe indices, positively oriented
//    (orient3d(p0, p1, p2, p3) > 0, i.e. det[p1-p0, p2-p0, p3-p0] > 0);
//  - outer cells (vertices[3] == kOuterVertex): vertices[0..2] a hull triangle ordered so that
//    its normal (p1-p0) x (p2-p0) points out of the hull; the cell is the region swept by the
//    triangle moved along its vertices' hull normals ([Cupisz12]).
// neighbours[i] is the cell across the face opposite vertices[i]. For an outer cell,
// neighbours[3] is the inner tetrahedron across its hull triangle and neighbours[0..2] the outer
// cells across its hull edges. Every link is set (no -1) in a valid cloud: the cells cover space.
// Clouds of 0-3 probes, or all-coplanar probes, have no cells (interpolation falls back, see the
// traversal system).
//
// Per-cell transforms ([Sukys14] sec. 4.2), one glm::mat4 per cell (column-major, as GLM):
//  - inner: columns 0..2 hold the 3x3 matrix T^-1 and column 3 holds (p3, 1); the barycentric
//    coordinates of p are (l0, l1, l2) = T^-1 (p - p3), l3 = 1 - l0 - l1 - l2;
//  - outer: the coefficients of the cubic in t whose root moves the hull triangle onto p
//    ([Cupisz12]: det[p0 + t n0 - p, p1 + t n1 - p, p2 + t n2 - p] = 0, every coefficient affine
//    in p): row k of the matrix dotted with (p, 1) gives the coefficient of t^(3-k), k = 0..3.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace penumbra::data {

inline constexpr std::int32_t kOuterVertex = -1;  // vertices[3] of an outer cell
inline constexpr int kProbeMinBands = 2;
inline constexpr int kProbeMaxBands = 4;
inline constexpr int kProbeDefaultBands = 3;  // 9 coefficients per colour, as [Cupisz12]

struct ProbeCell {
  std::array<std::int32_t, 4> vertices{};    // probe indices; vertices[3] == kOuterVertex: outer
  std::array<std::int32_t, 4> neighbours{};  // cell across the face opposite vertices[i]
  bool outer() const { return vertices[3] == kOuterVertex; }
};

struct ProbeCloud {
  int bands = kProbeDefaultBands;  // SH bands of the irradiance, kProbeMinBands..kProbeMaxBands
  std::vector<glm::vec3> positions;  // metres, world frame (z up), all finite, no duplicates
  // Irradiance SH (W/m^2 per unit solid angle basis, linear RGB, engine/sh conventions):
  // probe-major, then channel (r, g, b), then coefficient: sh[(probe * 3 + c) * bands^2 + i].
  std::vector<float> sh;
  std::vector<ProbeCell> cells;        // inner tetrahedra first, then outer cells
  std::vector<glm::mat4> transforms;   // one per cell (see above)
  std::vector<glm::vec3> hull_normals; // one per probe: unit outward normal on the hull, else 0
  std::uint32_t inner_count = 0;       // cells[0, inner_count) are inner tetrahedra

  std::size_t probe_count() const { return positions.size(); }
  std::size_t coeffs_per_probe() const { return static_cast<std::size_t>(3 * bands * bands); }
  const float* probe_sh(std::size_t probe) const { return sh.data() + probe * coeffs_per_probe(); }
};

}  // namespace penumbra::data
