#include "penumbra/systems/probe_bake/solid_mesh.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "penumbra/reference/scene.h"

namespace penumbra::probe_bake {
namespace {

// Welds positions that are bit-identical (glTF's seam duplicates are copies, not near misses).
std::vector<std::uint32_t> weld(const std::vector<glm::vec3>& positions, std::size_t& distinct) {
  struct Key {
    float x, y, z;
    bool operator<(const Key& o) const {
      return x != o.x ? x < o.x : (y != o.y ? y < o.y : z < o.z);
    }
  };
  std::map<Key, std::uint32_t> ids;
  std::vector<std::uint32_t> remap(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3& p = positions[i];
    const auto [it, added] =
        ids.emplace(Key{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f},  // + 0: -0 and 0 weld
                    static_cast<std::uint32_t>(ids.size()));
    remap[i] = it->second;
  }
  distinct = ids.size();
  return remap;
}

// Three directions no axis-aligned or diagonal face is parallel to.
constexpr std::array<std::array<float, 3>, 3> kParityDirections{
    {{0.5431f, 0.3197f, 0.7765f}, {-0.6142f, 0.7013f, -0.3617f}, {0.2287f, -0.8831f, -0.4098f}}};
constexpr int kMaxCrossings = 10000;

}  // namespace

MeshClosure mesh_closure(const data::MeshData& mesh) {
  MeshClosure c;
  const std::vector<std::uint32_t> id = weld(mesh.positions, c.welded_vertices);
  std::unordered_map<std::uint64_t, std::uint32_t> uses;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t v[3] = {id[mesh.indices[t]], id[mesh.indices[t + 1]],
                                id[mesh.indices[t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // degenerate: no area
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = std::min(v[e], v[(e + 1) % 3]), b = std::max(v[e], v[(e + 1) % 3]);
      ++uses[(std::uint64_t{a} << 32) | b];
    }
  }
  c.edges = uses.size();
  for (const auto& [edge, n] : uses) {
    if (n == 1) ++c.boundary_edges;
    if (n >= 3) ++c.nonmanifold_edges;
  }
  return c;
}

SolidMesh::SolidMesh(const data::MeshData& mesh, const glm::mat4& transform) {
  if (!mesh_closure(mesh).closed())
    throw std::invalid_argument("SolidMesh: mesh \"" + mesh.name + "\" is not closed");
  reference::SceneDesc d;
  d.meshes.push_back({mesh, transform, glm::vec3(0.0f)});
  scene_ = std::make_unique<reference::Scene>(d);
  lo_ = glm::vec3(std::numeric_limits<float>::max());
  hi_ = -lo_;
  for (const glm::vec3& p : mesh.positions) {
    const glm::vec3 w = glm::vec3(transform * glm::vec4(p, 1.0f));
    lo_ = glm::min(lo_, w);
    hi_ = glm::max(hi_, w);
  }
  step_ = 1e-5f * std::max(glm::length(hi_ - lo_), 1e-6f);
}

SolidMesh::~SolidMesh() = default;
SolidMesh::SolidMesh(SolidMesh&&) noexcept = default;
SolidMesh& SolidMesh::operator=(SolidMesh&&) noexcept = default;

bool SolidMesh::inside(const glm::vec3& p) const {
  if (!scene_ || glm::any(glm::lessThan(p, lo_)) || glm::any(glm::greaterThan(p, hi_)))
    return false;
  int votes = 0;
  for (const auto& d : kParityDirections) {
    const glm::vec3 dir = glm::normalize(glm::vec3(d[0], d[1], d[2]));
    glm::vec3 o = p;
    int crossings = 0;
    for (; crossings < kMaxCrossings; ++crossings) {
      const float t = scene_->hit_distance(o, dir, std::numeric_limits<float>::infinity());
      if (!(t < std::numeric_limits<float>::infinity())) break;
      o += (t + step_) * dir;  // past this crossing (a hit on a shared edge counts once)
    }
    votes += crossings % 2;
  }
  return votes >= 2;
}

}  // namespace penumbra::probe_bake
