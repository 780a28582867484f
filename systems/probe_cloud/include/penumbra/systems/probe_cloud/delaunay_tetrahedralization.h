// Delaunay tetrahedralization of a 3D point set by Bowyer-Watson insertion ([Sukys14] sec. 3.2,
// fig. 10) with exact predicates and a symbolic perturbation (exact_predicates.h), so the result
// is a valid Delaunay tetrahedralization for ANY input without duplicates, including grids
// (cospherical) and nearly flat sets. The hull is exact: instead of a big enclosing box the
// triangulation carries a symbolic point at infinity whose "ghost" cells are the hull faces.
// Coordinates are used as given (no scaling at all, so never a per-axis squash).
// Threading: a pure function; no shared state.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::probe_cloud {

inline constexpr std::int32_t kInfiniteVertex = -1;

struct DelaunayTetrahedralization {
  // cells[0, finite_count): tetrahedra, 4 point indices, orient3d > 0.
  // cells[finite_count, size): one ghost cell per hull triangle: vertices[0..2] the triangle
  // with (p1-p0) x (p2-p0) pointing out of the hull, vertices[3] == kInfiniteVertex.
  std::vector<std::array<std::int32_t, 4>> vertices;
  // neighbours[c][i]: the cell across the face opposite vertices[c][i] (always set). For a
  // ghost cell, [3] is the tetrahedron across its hull triangle and [0..2] the ghost cells across
  // its hull edges.
  std::vector<std::array<std::int32_t, 4>> neighbours;
  std::size_t finite_count = 0;
  std::size_t hull_count() const { return vertices.size() - finite_count; }
};

// Tetrahedralizes `points` (must be finite and pairwise distinct; duplicates are the caller's
// job, see probe_cloud_build.h). Fewer than 4 points, or all coplanar: an empty result.
// Points are inserted in a biased randomized (BRIO) order of Morton-sorted rounds, each located
// by a walk from the last created tetrahedron. Deterministic: same input, same output.
DelaunayTetrahedralization delaunay_tetrahedralize(std::span<const glm::dvec3> points);

}  // namespace penumbra::probe_cloud
