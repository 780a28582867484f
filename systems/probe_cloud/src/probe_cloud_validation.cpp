// Validation of a probe cloud's cells, links, Delaunay property, hull cover and transforms.
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "penumbra/systems/probe_cloud/exact_predicates.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

namespace penumbra::probe_cloud {
namespace {

constexpr std::size_t kMaxErrors = 20;

class Errors {
 public:
  template <typename... Args>
  void add(const Args&... args) {
    ++count_;
    if (list_.size() >= kMaxErrors) return;
    std::ostringstream s;
    (s << ... << args);
    list_.push_back(s.str());
  }
  std::size_t count() const { return count_; }
  std::vector<std::string> finish() && {
    if (count_ > list_.size()) {
      list_.push_back("... and " + std::to_string(count_ - list_.size()) + " more");
    }
    return std::move(list_);
  }

 private:
  std::vector<std::string> list_;
  std::size_t count_ = 0;
};

std::array<std::int32_t, 3> face(const data::ProbeCell& c, int k) {
  std::array<std::int32_t, 3> f{};
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    if (i != k) f[static_cast<std::size_t>(n++)] = c.vertices[static_cast<std::size_t>(i)];
  }
  std::sort(f.begin(), f.end());
  return f;
}

bool close(const glm::mat4& a, const glm::mat4& b, bool outer) {
  // Inner: compare T^-1 to its largest entry and p3 to its size; outer: each row to its size.
  for (int row = 0; row < 4; ++row) {
    float scale = 0;
    for (int col = 0; col < 4; ++col) {
      scale = std::max({scale, std::fabs(a[col][row]), std::fabs(b[col][row])});
    }
    if (!outer && row < 3) {
      for (int col = 0; col < 3; ++col) {
        for (int r = 0; r < 3; ++r) scale = std::max(scale, std::fabs(b[col][r]));
      }
    }
    for (int col = 0; col < 4; ++col) {
      if (std::fabs(a[col][row] - b[col][row]) > 1e-4f * scale + 1e-30f) return false;
    }
  }
  return true;
}

}  // namespace

ProbeCloudValidation validate_probe_cloud(const data::ProbeCloud& cloud) {
  Errors err;
  const std::size_t n = cloud.positions.size();
  const std::size_t cells = cloud.cells.size();
  if (cloud.bands < data::kProbeMinBands || cloud.bands > data::kProbeMaxBands) {
    err.add("bands ", cloud.bands, " outside ", data::kProbeMinBands, "..", data::kProbeMaxBands);
  } else if (cloud.sh.size() != n * cloud.coeffs_per_probe()) {
    err.add("sh has ", cloud.sh.size(), " floats, expected ", n * cloud.coeffs_per_probe());
  }
  if (cloud.hull_normals.size() != n) {
    err.add("hull_normals has ", cloud.hull_normals.size(), " entries for ", n, " probes");
  }
  if (cloud.transforms.size() != cells) {
    err.add("transforms has ", cloud.transforms.size(), " entries for ", cells, " cells");
  }
  if (cloud.inner_count > cells) err.add("inner_count ", cloud.inner_count, " > ", cells);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = cloud.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      err.add("probe ", i, ": position not finite");
    }
  }
  if (err.count() > 0) return {std::move(err).finish()};

  // Indices, kinds, ranges.
  std::vector<char> on_hull(n, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    const data::ProbeCell& cell = cloud.cells[c];
    const bool should_be_outer = c >= cloud.inner_count;
    if (cell.outer() != should_be_outer) {
      err.add("cell ", c, ": ", cell.outer() ? "outer" : "inner", " cell in the ",
              should_be_outer ? "outer" : "inner", " range");
    }
    for (int i = 0; i < (cell.outer() ? 3 : 4); ++i) {
      const std::int32_t v = cell.vertices[static_cast<std::size_t>(i)];
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        err.add("cell ", c, ": vertex ", v, " out of range");
    }
    for (std::int32_t nb : cell.neighbours) {
      if (nb < 0 || static_cast<std::size_t>(nb) >= cells) {
        err.add("cell ", c, ": neighbour ", nb, " out of range (cells must cover space)");
      }
    }
  }
  if (err.count() > 0) return {std::move(err).finish()};

  auto P = [&](std::int32_t v) { return glm::dvec3(cloud.positions[static_cast<std::size_t>(v)]); };
  glm::dvec3 centre(0.0);
  for (const glm::vec3& p : cloud.positions)
    centre += glm::dvec3(p) / double(std::max<std::size_t>(n, 1));
  double tet_volume = 0, hull_volume = 0, extent = 0;
  for (const glm::vec3& p : cloud.positions)
    extent = std::max(extent, glm::length(glm::dvec3(p) - centre));

  for (std::size_t c = 0; c < cells; ++c) {
    const data::ProbeCell& cell = cloud.cells[c];
    const auto& v = cell.vertices;
    if (!cell.outer()) {
      if (orient3d_sign(P(v[0]), P(v[1]), P(v[2]), P(v[3])) <= 0) {
        err.add("cell ", c, ": tetrahedron not positively oriented");
      }
      tet_volume +=
          orient3d(P(v[0]) - centre, P(v[1]) - centre, P(v[2]) - centre, P(v[3]) - centre) / 6.0;
    } else {
      for (int i = 0; i < 3; ++i) on_hull[static_cast<std::size_t>(v[i])] = 1;
      hull_volume +=
          glm::dot(P(v[0]) - centre, glm::cross(P(v[1]) - centre, P(v[2]) - centre)) / 6.0;
    }
    for (int k = 0; k < 4; ++k) {
      const std::int32_t nb = cell.neighbours[static_cast<std::size_t>(k)];
      const data::ProbeCell& other = cloud.cells[static_cast<std::size_t>(nb)];
      int back = -1;
      for (int j = 0; j < 4; ++j) {
        if (other.neighbours[static_cast<std::size_t>(j)] == static_cast<std::int32_t>(c)) back = j;
      }
      if (back < 0) {
        err.add("cell ", c, ": neighbour ", nb, " across face ", k, " does not link back");
        continue;
      }
      if (face(cell, k) != face(other, back)) {
        err.add("cell ", c, ": neighbour ", nb, " across face ", k, " shares another face");
        continue;
      }
      if (cell.outer()) {
        if ((k == 3) == other.outer()) {
          err.add("cell ", c, ": outer cell's neighbour ", k, " is ",
                  other.outer() ? "outer" : "inner",
                  " (face 3: the tetrahedron, 0-2: outer cells)");
        }
        if (k == 3) {  // the hull triangle faces away from the tetrahedron behind it
          const std::int32_t apex = other.vertices[static_cast<std::size_t>(back)];
          if (orient3d_sign(P(v[0]), P(v[1]), P(v[2]), P(apex)) >= 0) {
            err.add("cell ", c, ": hull triangle does not face out of the hull");
          }
        } else if (other.outer()) {  // convex hull: the next hull triangle bends inwards
          const std::int32_t apex = other.vertices[static_cast<std::size_t>(back)];
          if (orient3d_sign(P(v[0]), P(v[1]), P(v[2]), P(apex)) > 0) {
            err.add("cell ", c, ": hull not convex across the edge to cell ", nb);
          }
        }
      } else if (!other.outer() && static_cast<std::int32_t>(c) < nb) {
        const std::int32_t apex = other.vertices[static_cast<std::size_t>(back)];
        if (insphere(P(v[0]), P(v[1]), P(v[2]), P(v[3]), P(apex)) > 0) {
          err.add("cell ", c, ": vertex ", apex, " of neighbour ", nb,
                  " strictly inside its circumsphere (not Delaunay)");
        }
      }
    }
    if (!close(cloud.transforms[c], probe_cell_transform(cloud, static_cast<std::uint32_t>(c)),
               cell.outer())) {
      err.add("cell ", c, ": transform differs from the recomputed one");
    }
  }
  if (cells > 0) {
    // Divergence theorem: the hull faces enclose the volume the tetrahedra fill.
    const double tolerance = 1e-12 * double(cells) * extent * extent * extent + 1e-9 * hull_volume;
    if (std::fabs(tet_volume - hull_volume) > tolerance) {
      err.add("tetrahedra fill ", tet_volume, " m^3 but the hull encloses ", hull_volume, " m^3");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double len = glm::length(glm::dvec3(cloud.hull_normals[i]));
    if (on_hull[i] && std::fabs(len - 1.0) > 1e-3) {
      err.add("probe ", i, ": hull normal not unit (length ", len, ")");
    } else if (!on_hull[i] && len != 0) {
      err.add("probe ", i, ": not on the hull but has a hull normal");
    }
  }
  return {std::move(err).finish()};
}

}  // namespace penumbra::probe_cloud
