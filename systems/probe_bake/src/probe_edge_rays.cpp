// Edge rays (probe_edge_rays.h), [Sukys14] sec. 3.2.2.
#include "penumbra/systems/probe_bake/probe_edge_rays.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

namespace penumbra::probe_bake {
namespace {

std::uint64_t cell_key(const glm::vec3& p, float cell) {
  auto c = [&](int k) {
    return static_cast<std::uint64_t>(
        static_cast<std::uint32_t>(static_cast<int>(std::floor(p[k] / cell))) & 0x1FFFFF);
  };
  return (c(0) << 42) | (c(1) << 21) | c(2);
}

// Points in a hash grid, queried within a radius up to the cell size.
class PointGrid {
 public:
  explicit PointGrid(float cell) : cell_(cell) {}
  void add(const glm::vec3& p) { cells_[cell_key(p, cell_)].push_back(p); }
  bool any_within(const glm::vec3& p, float r) const {
    const float r2 = r * r;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(cell_key(p + cell_ * glm::vec3(dx, dy, dz), cell_));
          if (it == cells_.end()) continue;
          for (const glm::vec3& q : it->second)
            if (glm::dot(q - p, q - p) < r2) return true;
        }
    return false;
  }

 private:
  float cell_;
  std::unordered_map<std::uint64_t, std::vector<glm::vec3>> cells_;
};

}  // namespace

std::vector<glm::vec3> edge_ray_points(const BakeScene& scene, const reference::Scene& traced,
                                       std::span<const glm::vec3> positions,
                                       const EdgeRaySettings& s, EdgeRayStats* stats) {
  EdgeRayStats st;
  std::vector<glm::vec3> out;
  probe_cloud::ProbeCloudBuildSettings build;
  build.bands = 2;
  const data::ProbeCloud cloud = probe_cloud::build_probe_cloud(positions, {}, build);
  const auto& p = cloud.positions;
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (std::uint32_t c = 0; c < cloud.inner_count; ++c) {
    const auto& v = cloud.cells[c].vertices;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edges.emplace_back(std::min(v[i], v[j]), std::max(v[i], v[j]));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  st.edges = edges.size();
  if (edges.empty()) return out;
  // Hash cell: the mean edge length (the separation radius is clamped to it).
  double mean = 0;
  for (const auto& [a, b] : edges) mean += glm::length(p[b] - p[a]);
  const float cell = std::max(1e-3f, static_cast<float>(mean / double(edges.size())));
  PointGrid grid(cell);
  for (const glm::vec3& q : p) grid.add(q);
  for (const auto& [a, b] : edges) {
    const float len = glm::length(p[b] - p[a]);
    if (!(len > 0)) continue;
    for (int dir = 0; dir < 2; ++dir) {
      const glm::vec3 from = dir == 0 ? p[a] : p[b];
      const glm::vec3 d = ((dir == 0 ? p[b] : p[a]) - from) / len;
      const reference::Hit h = traced.first_hit(from, d, len);
      if (!h || !(h.distance < len)) continue;
      ++st.hits;
      // A ray along a surface (both vertices on it) crosses nothing ([Sukys14] sec. 3.2.2).
      if (std::abs(glm::dot(d, h.normal)) < s.grazing_cos) {
        ++st.grazing;
        continue;
      }
      // Fig. 14: the hit far enough (relative to the edge) from the ray's origin, whose side
      // the new probe goes on. (The thesis also tests the far vertex; across a thick wall that
      // vertex is on the other face, and a long hull edge from a probe just past a wall is
      // exactly the edge that leaks: the crowding test below keeps probes apart instead.)
      if (h.distance < s.min_fraction * len) {
        ++st.near_vertex;
        continue;
      }
      const glm::vec3 hit = from + h.distance * d;
      const float off = std::min(s.offset_fraction * len, 0.5f * h.distance);
      const glm::vec3 q = hit + off * h.normal;  // normal faces the ray: the origin's side
      if (scene.inside(q) || traced.occluded(hit + 1e-4f * h.normal, h.normal, off)) {
        ++st.blocked;
        continue;
      }
      if (grid.any_within(q, std::min(cell, s.min_separation * len))) {
        ++st.crowded;
        continue;
      }
      grid.add(q);
      out.push_back(q);
    }
  }
  st.added = out.size();
  if (stats) {
    stats->edges += st.edges;
    stats->hits += st.hits;
    stats->grazing += st.grazing;
    stats->near_vertex += st.near_vertex;
    stats->blocked += st.blocked;
    stats->crowded += st.crowded;
    stats->added += st.added;
  }
  return out;
}

}  // namespace penumbra::probe_bake
