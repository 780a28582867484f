// Bowyer-Watson insertion ([Sukys14] sec. 3.2, fig. 10): locate the point by a visibility walk,
// grow the cavity of tetrahedra whose circumsphere contains it (exact, perturbed insphere),
// replace the cavity by the cone from the point to its boundary faces. Ghost cells on the hull
// faces share a symbolic vertex at infinity, so the hull needs no enclosing box.
#include "penumbra/systems/probe_cloud/delaunay_tetrahedralization.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <glm/common.hpp>

#include "penumbra/systems/probe_cloud/exact_predicates.h"

namespace penumbra::probe_cloud {
namespace {

using Vertices = std::array<std::int32_t, 4>;
constexpr std::int32_t kInf = kInfiniteVertex;
constexpr std::int32_t kNone = -1;

struct Cell {
  Vertices v;
  std::array<std::int32_t, 4> n;
};

// 63-bit Morton key of a point quantised on a cube (uniform scale on every axis).
std::uint64_t spread21(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// BRIO ([Amenta03]): a seeded shuffle, then rounds of doubling size, each in Morton order.
std::vector<std::uint32_t> insertion_order(std::span<const glm::dvec3> points) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  auto next = [&state] {  // splitmix64: the same order on every platform
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[next() % i]);

  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::dvec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const double scale = extent > 0 ? double(0x1fffff) / extent : 0.0;
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 q = (points[i] - lo) * scale;
    key[i] = spread21(static_cast<std::uint64_t>(q.x)) |
             spread21(static_cast<std::uint64_t>(q.y)) << 1 |
             spread21(static_cast<std::uint64_t>(q.z)) << 2;
  }
  // Round boundaries: [0, n/2^k), ..., [n/4, n/2), [n/2, n).
  std::vector<std::size_t> bounds{n};
  while (bounds.back() > 64) bounds.push_back(bounds.back() / 2);
  bounds.push_back(0);
  std::reverse(bounds.begin(), bounds.end());
  for (std::size_t r = 0; r + 1 < bounds.size(); ++r) {
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(bounds[r]),
              order.begin() + static_cast<std::ptrdiff_t>(bounds[r + 1]),
              [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  }
  return order;
}

class Builder {
 public:
  explicit Builder(std::vector<glm::dvec3> pts) : p_(std::move(pts)) {
    // About 6.7 tetrahedra per point for random points, plus the hull: one allocation.
    const std::size_t expected = 7 * p_.size() + 64;
    cells_.reserve(expected);
    visit_.reserve(expected);
    in_conflict_.reserve(expected);
  }

  // Starts from the tetrahedron of points a, b, c, d (not coplanar) and its four ghosts.
  void init(std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d) {
    if (orient3d_sign(p_[a], p_[b], p_[c], p_[d]) < 0) std::swap(a, b);
    const Vertices t{a, b, c, d};
    cells_.push_back({t, {1, 2, 3, 4}});
    for (int i = 0; i < 4; ++i) {
      Vertices g = t;  // the face opposite t[i], seen from outside, infinity in slot 3
      g[i] = kInf;
      if (i != 3) {
        std::swap(g[i], g[3]);
      } else {
        std::swap(g[0], g[1]);
      }
      cells_.push_back({g, {kNone, kNone, kNone, 0}});
    }
    // Ghost-ghost links: two ghosts share the face {infinity, u, w} when both hold u and w.
    for (int g = 1; g <= 4; ++g) {
      for (int k = 0; k < 3; ++k) {
        const std::int32_t e0 = cells_[g].v[(k + 1) % 3], e1 = cells_[g].v[(k + 2) % 3];
        for (int h = 1; h <= 4; ++h) {
          if (h == g) continue;
          const Vertices& w = cells_[h].v;
          const bool has0 = w[0] == e0 || w[1] == e0 || w[2] == e0;
          const bool has1 = w[0] == e1 || w[1] == e1 || w[2] == e1;
          if (has0 && has1) cells_[g].n[k] = h;
        }
      }
    }
    last_ = 0;
    visit_.assign(cells_.size(), 0);
    in_conflict_.assign(cells_.size(), 0);
  }

  void insert(std::int32_t pi) {
    ++stamp_;
    const std::int32_t start = locate(pi);
    grow_cavity(start, pi);
    retriangulate(pi);
  }

  DelaunayTetrahedralization finish(const std::vector<std::uint32_t>& original) const {
    DelaunayTetrahedralization out;
    std::vector<std::int32_t> remap(cells_.size(), kNone);
    std::int32_t next = 0;
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t c = 0; c < cells_.size(); ++c) {
        if (dead(c)) continue;
        const bool ghost = cells_[c].v[3] == kInf;
        if (ghost == (pass == 1)) remap[c] = next++;
      }
      if (pass == 0) out.finite_count = static_cast<std::size_t>(next);
    }
    out.vertices.resize(static_cast<std::size_t>(next));
    out.neighbours.resize(static_cast<std::size_t>(next));
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      if (remap[c] == kNone) continue;
      const auto r = static_cast<std::size_t>(remap[c]);
      for (int i = 0; i < 4; ++i) {
        const std::int32_t v = cells_[c].v[i];
        out.vertices[r][i] = v == kInf ? kInf : static_cast<std::int32_t>(original[v]);
        out.neighbours[r][i] = remap[static_cast<std::size_t>(cells_[c].n[i])];
      }
    }
    return out;
  }

  const glm::dvec3& point(std::int32_t i) const { return p_[static_cast<std::size_t>(i)]; }

 private:
  bool dead(std::size_t c) const { return cells_[c].v[0] == kDead; }

  bool ghost(std::int32_t c) const { return cells_[static_cast<std::size_t>(c)].v[3] == kInf; }

  // Visibility walk from the last created cell; returns a cell in conflict with pi.
  std::int32_t locate(std::int32_t pi) {
    const glm::dvec3& q = point(pi);
    std::int32_t t = last_;
    if (dead(static_cast<std::size_t>(t))) t = any_live();
    if (ghost(t)) t = cells_[static_cast<std::size_t>(t)].n[3];
    std::int32_t from = kNone;
    const std::size_t cap = 4 * cells_.size() + 64;
    for (std::size_t step = 0; step < cap; ++step) {
      if (ghost(t)) return t;  // crossed a hull face strictly: q is outside that face
      const Cell& c = cells_[static_cast<std::size_t>(t)];
      const int offset = static_cast<int>(rng() & 3);  // stochastic face order ([Devillers02])
      std::int32_t next = kNone;
      for (int j = 0; j < 4 && next == kNone; ++j) {
        const int k = (j + offset) & 3;
        if (c.n[k] == from) continue;
        const Vertices& v = c.v;
        if (orient3d_sign(k == 0 ? q : point(v[0]), k == 1 ? q : point(v[1]),
                          k == 2 ? q : point(v[2]), k == 3 ? q : point(v[3])) < 0) {
          next = c.n[k];
        }
      }
      if (next == kNone) return t;  // q in the closed tetrahedron: strictly in its sphere
      from = t;
      t = next;
    }
    // Never expected for a Delaunay tetrahedralization; a scan keeps the build total.
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      if (!dead(c) && conflict(static_cast<std::int32_t>(c), pi)) {
        return static_cast<std::int32_t>(c);
      }
    }
    assert(false && "no cell in conflict");
    return last_;
  }

  std::int32_t any_live() const {
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      if (!dead(c)) return static_cast<std::int32_t>(c);
    }
    return 0;
  }

  std::uint32_t rng() {
    rng_ ^= rng_ << 13;
    rng_ ^= rng_ >> 17;
    rng_ ^= rng_ << 5;
    return rng_;
  }

  bool finite_conflict(std::int32_t t, std::int32_t pi) const {
    const Vertices& v = cells_[static_cast<std::size_t>(t)].v;
    return insphere_perturbed(point(v[0]), point(v[1]), point(v[2]), point(v[3]), point(pi),
                              static_cast<std::uint32_t>(v[0]), static_cast<std::uint32_t>(v[1]),
                              static_cast<std::uint32_t>(v[2]), static_cast<std::uint32_t>(v[3]),
                              static_cast<std::uint32_t>(pi)) > 0;
  }

  bool conflict(std::int32_t t, std::int32_t pi) const {
    const Cell& c = cells_[static_cast<std::size_t>(t)];
    if (c.v[3] != kInf) return finite_conflict(t, pi);
    const int o = orient3d_sign(point(c.v[0]), point(c.v[1]), point(c.v[2]), point(pi));
    if (o != 0) return o > 0;
    // On the hull face's plane: in conflict iff inside the face's circumcircle, which is the
    // plane's section of the finite neighbour's (perturbed) circumsphere.
    return finite_conflict(c.n[3], pi);
  }

  void grow_cavity(std::int32_t start, std::int32_t pi) {
    cavity_.clear();
    boundary_.clear();
    mark(start, true);
    cavity_.push_back(start);
    for (std::size_t head = 0; head < cavity_.size(); ++head) {
      const std::int32_t t = cavity_[head];
      for (int k = 0; k < 4; ++k) {
        const std::int32_t nb = cells_[static_cast<std::size_t>(t)].n[k];
        const auto s = static_cast<std::size_t>(nb);
        if (visit_[s] == stamp_) {
          if (!in_conflict_[s]) boundary_.push_back({t, k, nb, {}, 0});
          continue;
        }
        const bool hit = conflict(nb, pi);
        mark(nb, hit);
        if (hit) {
          cavity_.push_back(nb);
        } else {
          boundary_.push_back({t, k, nb, {}, 0});
        }
      }
    }
    for (Face& f : boundary_) {
      // Copy now: the cavity's slots are reused before every outside link is redirected.
      f.v = cells_[static_cast<std::size_t>(f.inside)].v;
      const std::array<std::int32_t, 4>& back = cells_[static_cast<std::size_t>(f.outside)].n;
      f.back = static_cast<int>(std::find(back.begin(), back.end(), f.inside) - back.begin());
    }
  }

  void mark(std::int32_t t, bool hit) {
    const auto s = static_cast<std::size_t>(t);
    visit_[s] = stamp_;
    in_conflict_[s] = hit;
  }

  std::int32_t new_cell() {
    if (!free_.empty()) {
      const std::int32_t c = free_.back();
      free_.pop_back();
      return c;
    }
    cells_.push_back({});
    visit_.push_back(0);
    in_conflict_.push_back(0);
    return static_cast<std::int32_t>(cells_.size() - 1);
  }

  void retriangulate(std::int32_t pi) {
    for (std::int32_t t : cavity_) {
      cells_[static_cast<std::size_t>(t)].v[0] = kDead;
      free_.push_back(t);
    }
    // Edge table: the faces through pi of the new cells meet in pairs along cavity-boundary
    // edges; a small open-addressed table, cleared by stamp, links them.
    std::size_t size = 16;
    while (size < 4 * 3 * boundary_.size()) size *= 2;
    if (table_.size() < size) table_.resize(size);
    ++table_stamp_;
    const std::size_t mask = size - 1;
    std::int32_t last_finite = kNone;
    for (const Face& f : boundary_) {
      const std::int32_t c = new_cell();
      Cell& cell = cells_[static_cast<std::size_t>(c)];
      cell.v = f.v;
      cell.v[f.k] = pi;
      cell.n[f.k] = f.outside;
      cells_[static_cast<std::size_t>(f.outside)].n[f.back] = c;
      if (cell.v[3] != kInf) last_finite = c;
      for (int j = 0; j < 4; ++j) {
        if (j == f.k) continue;
        // Face opposite j holds pi and the two vertices other than v[j] and v[k].
        std::int32_t a = kNone, b = kNone;
        for (int l = 0; l < 4; ++l) {
          if (l == j || l == f.k) continue;
          (a == kNone ? a : b) = cell.v[l];
        }
        if (a > b) std::swap(a, b);
        const std::uint64_t key = (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
        std::size_t h = static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> 40) & mask;
        for (;; h = (h + 1) & mask) {
          Slot& s = table_[h];
          if (s.stamp != table_stamp_) {
            s = {key, c, j, table_stamp_};
            break;
          }
          if (s.key == key) {
            cells_[static_cast<std::size_t>(c)].n[j] = s.cell;
            cells_[static_cast<std::size_t>(s.cell)].n[s.face] = c;
            break;
          }
        }
      }
    }
    if (last_finite != kNone) last_ = last_finite;
  }

  static constexpr std::int32_t kDead = std::numeric_limits<std::int32_t>::min();

  struct Face {
    std::int32_t inside;  // the cavity cell
    int k;                // its face opposite v[k]
    std::int32_t outside;
    Vertices v;
    int back;  // the slot of `outside` that links to `inside`
  };
  struct Slot {
    std::uint64_t key = 0;
    std::int32_t cell = 0;
    int face = 0;
    std::uint32_t stamp = 0;
  };

  std::vector<glm::dvec3> p_;
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> visit_;
  std::vector<std::uint8_t> in_conflict_;
  std::vector<std::int32_t> free_, cavity_;
  std::vector<Face> boundary_;
  std::vector<Slot> table_;
  std::uint32_t stamp_ = 0, table_stamp_ = 0, rng_ = 2463534242u;
  std::int32_t last_ = 0;
};

// True when a, b, c are collinear (exactly): all three coordinate projections are degenerate.
bool collinear(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  // orient3d with the fourth point lifted one unit off a projection plane is that
  // projection's exact orient2d.
  auto proj = [](const glm::dvec3& p, int drop) {
    return drop == 0   ? glm::dvec3(p.y, p.z, 0)
           : drop == 1 ? glm::dvec3(p.z, p.x, 0)
                       : glm::dvec3(p.x, p.y, 0);
  };
  for (int drop = 0; drop < 3; ++drop) {
    if (orient3d_sign(proj(a, drop), proj(b, drop), proj(c, drop), glm::dvec3(0, 0, 1)) != 0) {
      return false;
    }
  }
  return true;
}

}  // namespace

DelaunayTetrahedralization delaunay_tetrahedralize(std::span<const glm::dvec3> points) {
  if (points.size() < 4) return {};
  const std::vector<std::uint32_t> order = insertion_order(points);
  std::vector<glm::dvec3> sorted(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = points[order[i]];

  // The first four affinely independent points in insertion order start the triangulation.
  const std::int32_t n = static_cast<std::int32_t>(sorted.size());
  std::int32_t i2 = kNone, i3 = kNone;
  for (std::int32_t i = 2; i < n && i2 == kNone; ++i) {
    if (!collinear(sorted[0], sorted[1], sorted[static_cast<std::size_t>(i)])) i2 = i;
  }
  if (i2 == kNone) return {};
  for (std::int32_t i = 2; i < n && i3 == kNone; ++i) {
    if (i != i2 && orient3d_sign(sorted[0], sorted[1], sorted[static_cast<std::size_t>(i2)],
                                 sorted[static_cast<std::size_t>(i)]) != 0) {
      i3 = i;
    }
  }
  if (i3 == kNone) return {};

  Builder builder(std::move(sorted));
  builder.init(0, 1, i2, i3);
  for (std::int32_t i = 2; i < n; ++i) {
    if (i != i2 && i != i3) builder.insert(i);
  }
  return builder.finish(order);
}

}  // namespace penumbra::probe_cloud
