// Probe cloud build: duplicate merge, Delaunay tetrahedralization, outer cells ([Cupisz12]),
// hull normals and per-cell transforms ([Sukys14] sec. 4.2).
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "penumbra/systems/probe_cloud/delaunay_tetrahedralization.h"

namespace penumbra::probe_cloud {
namespace {

// Merges probes closer than `distance` to an earlier kept probe: a hash grid of cell size
// `distance` (open addressing, a linked list of kept probes per cell), 27 cells searched;
// distance <= 0 merges exact duplicates only (cell size 0: one cell per position).
std::vector<std::uint32_t> merge_duplicates(std::span<const glm::vec3> positions, float distance,
                                            std::vector<std::uint32_t>& kept) {
  const std::size_t n = positions.size();
  std::vector<std::uint32_t> map(n);
  const double cell = distance > 0 ? double(distance) : 0.0;
  const double d2 = cell * cell;
  using Key = std::array<std::int64_t, 3>;
  auto key_of = [&](const glm::vec3& p) -> Key {
    if (cell == 0) {  // exact duplicates: the coordinates' bits (+0 and -0 alike)
      auto bits = [](float v) {
        std::uint32_t u;
        const float w = v == 0.0f ? 0.0f : v;
        std::memcpy(&u, &w, sizeof u);
        return static_cast<std::int64_t>(u);
      };
      return {bits(p.x), bits(p.y), bits(p.z)};
    }
    auto q = [&](float v) {
      return static_cast<std::int64_t>(std::clamp(std::floor(double(v) / cell), -1e15, 1e15));
    };
    return {q(p.x), q(p.y), q(p.z)};
  };
  auto hash = [](const Key& k) {
    std::uint64_t h = static_cast<std::uint64_t>(k[0]) * 0x9e3779b97f4a7c15ULL;
    h = (h ^ (h >> 29)) + static_cast<std::uint64_t>(k[1]) * 0xc2b2ae3d27d4eb4fULL;
    h = (h ^ (h >> 31)) + static_cast<std::uint64_t>(k[2]) * 0x165667b19e3779f9ULL;
    return h ^ (h >> 32);
  };
  constexpr std::uint32_t kEmpty = 0xffffffffu;
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  std::vector<Key> slot_key(size);
  std::vector<std::uint32_t> head(size, kEmpty), next;  // per slot: newest kept probe
  next.reserve(n);
  auto find_slot = [&](const Key& k) {
    std::size_t h = hash(k) & (size - 1);
    while (head[h] != kEmpty && slot_key[h] != k) h = (h + 1) & (size - 1);
    return h;
  };
  const int r = cell > 0 ? 1 : 0;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = positions[i];
    const Key k = key_of(p);
    std::uint32_t found = kEmpty;
    for (int dx = -r; dx <= r && found == kEmpty; ++dx) {
      for (int dy = -r; dy <= r && found == kEmpty; ++dy) {
        for (int dz = -r; dz <= r && found == kEmpty; ++dz) {
          const std::size_t h = find_slot({k[0] + dx, k[1] + dy, k[2] + dz});
          for (std::uint32_t j = head[h]; j != kEmpty; j = next[j]) {
            const glm::dvec3 d = glm::dvec3(positions[kept[j]]) - glm::dvec3(p);
            if ((d.x == 0 && d.y == 0 && d.z == 0) || glm::dot(d, d) < d2) {
              found = j;
              break;
            }
          }
        }
      }
    }
    if (found != kEmpty) {
      map[i] = found;
      continue;
    }
    const auto id = static_cast<std::uint32_t>(kept.size());
    map[i] = id;
    kept.push_back(static_cast<std::uint32_t>(i));
    const std::size_t h = find_slot(k);
    slot_key[h] = k;
    next.push_back(head[h]);
    head[h] = id;
  }
  return map;
}

glm::dvec3 pos(const data::ProbeCloud& cloud, std::int32_t i) {
  return glm::dvec3(cloud.positions[static_cast<std::size_t>(i)]);
}

}  // namespace

std::size_t snap_to_box_faces(std::span<glm::vec3> positions, double relative) {
  if (positions.empty() || !(relative > 0)) return 0;
  glm::vec3 lo = positions[0], hi = lo;
  for (const glm::vec3& p : positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  // The shortest side sets the tolerance: a long strip's far ends do not widen its narrow axes'.
  const double side = std::min({double(hi.x) - lo.x, double(hi.y) - lo.y, double(hi.z) - lo.z});
  const double tolerance = relative * side;
  std::size_t moved = 0;
  for (int k = 0; k < 3; ++k) {
    for (glm::vec3& p : positions) {
      if (p[k] != lo[k] && double(p[k]) - lo[k] <= tolerance) {
        p[k] = lo[k], ++moved;
      } else if (p[k] != hi[k] && double(hi[k]) - p[k] <= tolerance) {
        p[k] = hi[k], ++moved;
      }
    }
  }
  return moved;
}

glm::mat4 probe_cell_transform(const data::ProbeCloud& cloud, std::uint32_t cell) {
  const data::ProbeCell& c = cloud.cells[cell];
  const glm::dvec3 p0 = pos(cloud, c.vertices[0]), p1 = pos(cloud, c.vertices[1]),
                   p2 = pos(cloud, c.vertices[2]);
  glm::mat4 m(0.0f);
  if (!c.outer()) {
    // [Sukys14] sec. 4.2: (l0, l1, l2) = T^-1 (p - p3), T = [p0 - p3, p1 - p3, p2 - p3].
    const glm::dvec3 p3 = pos(cloud, c.vertices[3]);
    const glm::dmat3 inv = glm::inverse(glm::dmat3(p0 - p3, p1 - p3, p2 - p3));
    for (int col = 0; col < 3; ++col) m[col] = glm::vec4(glm::vec3(inv[col]), 0.0f);
    m[3] = glm::vec4(glm::vec3(p3), 1.0f);
    return m;
  }
  // [Cupisz12]: det[p0 + t n0 - p, p1 + t n1 - p, p2 + t n2 - p] = sum_k (row_k . (p, 1)) t^(3-k).
  const glm::dvec3 n0(cloud.hull_normals[static_cast<std::size_t>(c.vertices[0])]),
      n1(cloud.hull_normals[static_cast<std::size_t>(c.vertices[1])]),
      n2(cloud.hull_normals[static_cast<std::size_t>(c.vertices[2])]);
  const glm::dvec3 n12 = glm::cross(n1, n2), n20 = glm::cross(n2, n0), n01 = glm::cross(n0, n1);
  const glm::dvec3 p12 = glm::cross(p1, p2), p20 = glm::cross(p2, p0), p01 = glm::cross(p0, p1);
  const std::array<glm::dvec3, 4> grad{
      glm::dvec3(0.0), -(n12 + n20 + n01),
      glm::cross(p1 - p2, n0) + glm::cross(p2 - p0, n1) + glm::cross(p0 - p1, n2),
      -(p12 + p20 + p01)};
  const std::array<double, 4> constant{
      glm::dot(n0, n12), glm::dot(p0, n12) + glm::dot(p1, n20) + glm::dot(p2, n01),
      glm::dot(n0, p12) + glm::dot(n1, p20) + glm::dot(n2, p01), glm::dot(p0, p12)};
  for (int k = 0; k < 4; ++k) {
    m[0][k] = static_cast<float>(grad[static_cast<std::size_t>(k)].x);
    m[1][k] = static_cast<float>(grad[static_cast<std::size_t>(k)].y);
    m[2][k] = static_cast<float>(grad[static_cast<std::size_t>(k)].z);
    m[3][k] = static_cast<float>(constant[static_cast<std::size_t>(k)]);
  }
  return m;
}

data::ProbeCloud build_probe_cloud(std::span<const glm::vec3> positions, std::span<const float> sh,
                                   const ProbeCloudBuildSettings& settings,
                                   ProbeCloudBuildReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  const int bands = settings.bands;
  if (bands < data::kProbeMinBands || bands > data::kProbeMaxBands) {
    throw std::invalid_argument("build_probe_cloud: bands " + std::to_string(bands) +
                                " outside 2..4");
  }
  const std::size_t coeffs = static_cast<std::size_t>(3 * bands * bands);
  if (!sh.empty() && sh.size() != positions.size() * coeffs) {
    throw std::invalid_argument("build_probe_cloud: sh has " + std::to_string(sh.size()) +
                                " floats, expected " + std::to_string(positions.size() * coeffs) +
                                " (" + std::to_string(coeffs) + " per probe) or none");
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3& p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw std::invalid_argument("build_probe_cloud: position " + std::to_string(i) +
                                  " is not finite (NaN or infinity)");
    }
  }

  data::ProbeCloud cloud;
  cloud.bands = bands;
  std::vector<glm::vec3> snapped(positions.begin(), positions.end());
  const std::size_t moved = snap_to_box_faces(snapped, settings.face_snap);
  std::vector<std::uint32_t> kept;
  std::vector<std::uint32_t> map = merge_duplicates(snapped, settings.merge_distance, kept);
  const std::size_t n = kept.size();
  cloud.positions.resize(n);
  for (std::size_t k = 0; k < n; ++k) cloud.positions[k] = snapped[kept[k]];
  cloud.sh.assign(n * coeffs, 0.0f);
  if (!sh.empty()) {  // the mean SH of the probes merged into each kept one
    std::vector<std::uint32_t> count(n, 0);
    for (std::size_t i = 0; i < positions.size(); ++i) {
      ++count[map[i]];
      for (std::size_t c = 0; c < coeffs; ++c) cloud.sh[map[i] * coeffs + c] += sh[i * coeffs + c];
    }
    for (std::size_t k = 0; k < n; ++k) {
      const float inv = 1.0f / static_cast<float>(count[k]);
      for (std::size_t c = 0; c < coeffs; ++c) cloud.sh[k * coeffs + c] *= inv;
    }
  }
  cloud.hull_normals.assign(n, glm::vec3(0.0f));

  std::vector<glm::dvec3> points(n);
  for (std::size_t k = 0; k < n; ++k) points[k] = glm::dvec3(cloud.positions[k]);
  const DelaunayTetrahedralization dt = delaunay_tetrahedralize(points);
  cloud.inner_count = static_cast<std::uint32_t>(dt.finite_count);
  cloud.cells.resize(dt.vertices.size());
  for (std::size_t c = 0; c < dt.vertices.size(); ++c) {
    cloud.cells[c].vertices = dt.vertices[c];
    cloud.cells[c].neighbours = dt.neighbours[c];
  }

  // Hull normals: the angle-weighted mean of the adjacent hull faces' outward unit normals.
  std::vector<glm::dvec3> normal(n, glm::dvec3(0.0));
  for (std::size_t c = dt.finite_count; c < dt.vertices.size(); ++c) {
    const auto& v = dt.vertices[c];
    const glm::dvec3 face =
        glm::normalize(glm::cross(points[v[1]] - points[v[0]], points[v[2]] - points[v[0]]));
    for (int i = 0; i < 3; ++i) {
      const glm::dvec3 a = glm::normalize(points[v[(i + 1) % 3]] - points[v[i]]);
      const glm::dvec3 b = glm::normalize(points[v[(i + 2) % 3]] - points[v[i]]);
      const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
      normal[static_cast<std::size_t>(v[i])] += angle * face;
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (glm::dot(normal[k], normal[k]) > 0) {
      cloud.hull_normals[k] = glm::vec3(glm::normalize(normal[k]));
    }
  }
  cloud.transforms.resize(cloud.cells.size());
  for (std::size_t c = 0; c < cloud.cells.size(); ++c) {
    cloud.transforms[c] = probe_cell_transform(cloud, static_cast<std::uint32_t>(c));
  }

  if (report != nullptr) {
    report->input_points = positions.size();
    report->merged_duplicates = positions.size() - n;
    report->snapped_coordinates = moved;
    report->tetrahedra = dt.finite_count;
    report->outer_cells = dt.hull_count();
    report->kept_index = std::move(map);
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return cloud;
}

}  // namespace penumbra::probe_cloud
