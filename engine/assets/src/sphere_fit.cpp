#include "penumbra/assets/sphere_fit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace penumbra::assets {
namespace {

using Clock = std::chrono::steady_clock;
using glm::dvec3;
constexpr double kPi = std::numbers::pi;

// Counter-based random numbers (splitmix64), so every sample depends only on (seed, stream,
// index) and results do not depend on the thread count.
std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

enum Stream : std::uint64_t { kSurface = 1, kVoxel, kSeeding, kEval, kCoverage };

struct Rng {
  std::uint64_t state;
  Rng(std::uint64_t seed, Stream stream, std::uint64_t index)
      : state(mix64(seed ^ mix64(static_cast<std::uint64_t>(stream) ^ mix64(index)))) {}
  double uniform() {
    state = mix64(state);
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  }
};

double dist2(const dvec3& a, const dvec3& b) {
  const dvec3 d = a - b;
  return glm::dot(d, d);
}

template <class F>
void parallel_for(std::size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                    });
}

struct Progress {
  const std::function<void(double, std::string_view)>* fn;
  void operator()(double f, std::string_view stage) const {
    if (*fn) (*fn)(std::clamp(f, 0.0, 1.0), stage);
  }
};

// The mesh in double precision, validated.
struct Prepared {
  std::string name;
  std::vector<dvec3> verts;
  std::vector<std::array<dvec3, 3>> tris;
  std::vector<dvec3> used_vertices;
  dvec3 lo{0}, hi{0};
  double diag = 0;
};

Prepared prepare(const data::MeshData& mesh) {
  Prepared m;
  m.name = mesh.name.empty() ? std::string("mesh") : mesh.name;
  if (mesh.indices.size() < 3) throw FitError(m.name, "no triangles");
  if (mesh.indices.size() % 3 != 0) throw FitError(m.name, "index count not a multiple of 3");
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw FitError(m.name, "non-finite position of vertex " + std::to_string(i));
  }
  std::vector<unsigned char> used(mesh.positions.size(), 0);
  m.lo = dvec3(std::numeric_limits<double>::max());
  m.hi = -m.lo;
  m.tris.reserve(mesh.indices.size() / 3);
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    std::array<dvec3, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = mesh.indices[t + static_cast<std::size_t>(k)];
      if (i >= mesh.positions.size())
        throw FitError(m.name, "index " + std::to_string(i) + " out of range");
      used[i] = 1;
      tri[static_cast<std::size_t>(k)] = dvec3(mesh.positions[i]);
      m.lo = glm::min(m.lo, tri[static_cast<std::size_t>(k)]);
      m.hi = glm::max(m.hi, tri[static_cast<std::size_t>(k)]);
    }
    m.tris.push_back(tri);
  }
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) m.used_vertices.emplace_back(mesh.positions[i]);
  const dvec3 e = m.hi - m.lo;
  m.diag = glm::length(e);
  const double thin = std::min({e.x, e.y, e.z});
  if (!(m.diag > 0) || thin <= 1e-6 * m.diag) {
    char box[160];
    std::snprintf(box, sizeof box, "%.4g x %.4g x %.4g", e.x, e.y, e.z);
    throw FitError(m.name, std::string("flat mesh (bounding box ") + box +
                               "): it encloses no volume to fit spheres to");
  }
  return m;
}

// Area-weighted uniform points on the triangles.
class SurfaceSampler {
 public:
  explicit SurfaceSampler(const Prepared& m) : m_(m) {
    cdf_.reserve(m.tris.size());
    double total = 0;
    for (const auto& t : m.tris) {
      total += 0.5 * glm::length(glm::cross(t[1] - t[0], t[2] - t[0]));
      cdf_.push_back(total);
    }
    if (!(total > 0)) throw FitError(m.name, "zero surface area");
  }
  dvec3 sample(Rng& rng) const {
    const double u = rng.uniform() * cdf_.back();
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const std::size_t t =
        std::min<std::size_t>(static_cast<std::size_t>(it - cdf_.begin()), cdf_.size() - 1);
    const auto& tri = m_.tris[t];
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    return (1 - r1) * tri[0] + r1 * (1 - r2) * tri[1] + r1 * r2 * tri[2];
  }
  std::vector<dvec3> samples(std::size_t n, std::uint64_t seed, Stream stream) const {
    std::vector<dvec3> out(n);
    parallel_for(n, [&](std::size_t i) {
      Rng rng(seed, stream, i);
      out[i] = sample(rng);
    });
    return out;
  }

 private:
  const Prepared& m_;
  std::vector<double> cdf_;
};

// Ray parity along +x, +y, +z, two odd counts of three: inside. One uniform 2D grid of
// triangle references per ray axis over the projection.
class InsideTester {
 public:
  explicit InsideTester(const Prepared& m) : m_(m) {
    const double target = 2.0 * static_cast<double>(m.tris.size());
    for (int a = 0; a < 3; ++a) {
      Grid& g = grids_[static_cast<std::size_t>(a)];
      g.u = (a + 1) % 3;
      g.v = (a + 2) % 3;
      g.lo_u = m.lo[g.u];
      g.lo_v = m.lo[g.v];
      const double eu = m.hi[g.u] - m.lo[g.u], ev = m.hi[g.v] - m.lo[g.v];
      g.nu = std::clamp(static_cast<int>(std::lround(std::sqrt(target * eu / ev))), 1, 512);
      g.nv = std::clamp(static_cast<int>(std::lround(target / g.nu)), 1, 512);
      g.inv_u = g.nu / eu;
      g.inv_v = g.nv / ev;
      std::vector<std::array<int, 4>> ranges(m.tris.size());
      g.start.assign(static_cast<std::size_t>(g.nu) * static_cast<std::size_t>(g.nv) + 1, 0);
      for (std::size_t t = 0; t < m.tris.size(); ++t) {
        const auto& tri = m.tris[t];
        double u0 = tri[0][g.u], u1 = u0, v0 = tri[0][g.v], v1 = v0;
        for (int k = 1; k < 3; ++k) {
          u0 = std::min(u0, tri[static_cast<std::size_t>(k)][g.u]);
          u1 = std::max(u1, tri[static_cast<std::size_t>(k)][g.u]);
          v0 = std::min(v0, tri[static_cast<std::size_t>(k)][g.v]);
          v1 = std::max(v1, tri[static_cast<std::size_t>(k)][g.v]);
        }
        auto& r = ranges[t];
        r = {g.cell_u(u0), g.cell_u(u1), g.cell_v(v0), g.cell_v(v1)};
        for (int iv = r[2]; iv <= r[3]; ++iv)
          for (int iu = r[0]; iu <= r[1]; ++iu) ++g.start[g.cell(iu, iv) + 1];
      }
      for (std::size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
      g.tris.resize(g.start.back());
      std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
      for (std::size_t t = 0; t < m.tris.size(); ++t) {
        const auto& r = ranges[t];
        for (int iv = r[2]; iv <= r[3]; ++iv)
          for (int iu = r[0]; iu <= r[1]; ++iu)
            g.tris[fill[g.cell(iu, iv)]++] = static_cast<std::uint32_t>(t);
      }
    }
  }

  bool inside(const dvec3& p) const {
    int votes = 0;
    for (int a = 0; a < 3; ++a) votes += crossings(a, p) & 1;
    return votes >= 2;
  }

 private:
  struct Grid {
    int u = 0, v = 0, nu = 1, nv = 1;
    double lo_u = 0, lo_v = 0, inv_u = 0, inv_v = 0;
    std::vector<std::uint32_t> start;  // CSR over cells
    std::vector<std::uint32_t> tris;
    int cell_u(double x) const {
      return std::clamp(static_cast<int>(std::floor((x - lo_u) * inv_u)), 0, nu - 1);
    }
    int cell_v(double x) const {
      return std::clamp(static_cast<int>(std::floor((x - lo_v) * inv_v)), 0, nv - 1);
    }
    std::size_t cell(int iu, int iv) const {
      return static_cast<std::size_t>(iv) * static_cast<std::size_t>(nu) +
             static_cast<std::size_t>(iu);
    }
  };

  int crossings(int a, const dvec3& p) const {
    const Grid& g = grids_[static_cast<std::size_t>(a)];
    const double pu = p[g.u], pv = p[g.v];
    const double fu = (pu - g.lo_u) * g.inv_u, fv = (pv - g.lo_v) * g.inv_v;
    if (!(fu >= 0 && fu < g.nu && fv >= 0 && fv < g.nv)) return 0;
    const std::size_t c = g.cell(static_cast<int>(fu), static_cast<int>(fv));
    int n = 0;
    for (std::uint32_t k = g.start[c]; k < g.start[c + 1]; ++k) {
      const auto& t = m_.tris[g.tris[k]];
      // Edge functions of the projected triangle; e_i weighs vertex i.
      const auto edge = [&](const dvec3& s, const dvec3& e) {
        return (e[g.u] - s[g.u]) * (pv - s[g.v]) - (e[g.v] - s[g.v]) * (pu - s[g.u]);
      };
      const double e0 = edge(t[1], t[2]), e1 = edge(t[2], t[0]), e2 = edge(t[0], t[1]);
      if (!((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0))) continue;
      const double hit = (e0 * t[0][a] + e1 * t[1][a] + e2 * t[2][a]) / (e0 + e1 + e2);
      if (hit > p[a]) ++n;
    }
    return n;
  }

  const Prepared& m_;
  std::array<Grid, 3> grids_;
};

// |generalized winding number| at p (Jacobson et al. 2013; solid angles by Van Oosterom and
// Strackee 1983): 1 inside a closed surface, 0 outside, below 1/2 everywhere for an open sheet.
double winding_number(const Prepared& m, const dvec3& p) {
  double sum = 0;
  for (const auto& t : m.tris) {
    const dvec3 a = t[0] - p, b = t[1] - p, c = t[2] - p;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den =
        la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    sum += 2 * std::atan2(num, den);
  }
  return std::abs(sum) / (4 * kPi);
}

// The bounding box in voxels: a jittered point per voxel classified by InsideTester; the
// variational cost counts inside voxel centres in a ball with per-row prefix sums.
class VoxelGrid {
 public:
  VoxelGrid(const Prepared& m, const InsideTester& tester, int cells, std::uint64_t seed)
      : lo_(m.lo) {
    const dvec3 e = m.hi - m.lo;
    double h = std::cbrt(e.x * e.y * e.z / std::max(cells, 1));
    for (;;) {
      for (int a = 0; a < 3; ++a)
        n_[static_cast<std::size_t>(a)] = std::max(1, static_cast<int>(std::lround(e[a] / h)));
      if (static_cast<double>(n_[0]) * n_[1] * n_[2] <= 2.0 * std::max(cells, 1)) break;
      h *= 1.25;
    }
    h_ = dvec3(e.x / n_[0], e.y / n_[1], e.z / n_[2]);
    voxel_volume_ = h_.x * h_.y * h_.z;
    const std::size_t total = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
    std::vector<dvec3> pts(total);
    std::vector<unsigned char> in(total);
    parallel_for(total, [&](std::size_t i) {
      Rng rng(seed, kVoxel, i);
      const dvec3 idx(static_cast<double>(i % n_[0]), static_cast<double>((i / n_[0]) % n_[1]),
                      static_cast<double>(i / (static_cast<std::size_t>(n_[0]) * n_[1])));
      pts[i] = lo_ + (idx + dvec3(rng.uniform(), rng.uniform(), rng.uniform())) * h_;
      in[i] = tester.inside(pts[i]) ? 1 : 0;
    });
    const std::size_t rows = static_cast<std::size_t>(n_[1]) * n_[2];
    prefix_.assign(rows * (static_cast<std::size_t>(n_[0]) + 1), 0);
    for (std::size_t r = 0; r < rows; ++r) {
      std::uint32_t* row = &prefix_[r * (static_cast<std::size_t>(n_[0]) + 1)];
      for (int x = 0; x < n_[0]; ++x) {
        const std::size_t i = r * static_cast<std::size_t>(n_[0]) + static_cast<std::size_t>(x);
        row[x + 1] = row[x] + in[i];
        if (in[i]) inside_points_.push_back(pts[i]);
      }
    }
  }

  const std::vector<dvec3>& inside_points() const { return inside_points_; }
  std::size_t cells() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
  double voxel_volume() const { return voxel_volume_; }

  // Inside voxel centres within the ball.
  std::size_t count_in_ball(const dvec3& c, double r) const {
    const auto range = [&](int a, double centre, double half) {
      const double f0 = (centre - half - lo_[a]) / h_[a] - 0.5;
      const double f1 = (centre + half - lo_[a]) / h_[a] - 0.5;
      const int n = n_[static_cast<std::size_t>(a)];
      return std::pair<int, int>(
          std::max(0, static_cast<int>(std::ceil(std::max(f0, -1.0)))),
          std::min(n - 1, static_cast<int>(std::floor(std::min(f1, static_cast<double>(n))))));
    };
    std::size_t count = 0;
    const auto [z0, z1] = range(2, c.z, r);
    for (int z = z0; z <= z1; ++z) {
      const double dz = lo_.z + (z + 0.5) * h_.z - c.z;
      const double rz2 = r * r - dz * dz;
      if (rz2 < 0) continue;
      const auto [y0, y1] = range(1, c.y, std::sqrt(rz2));
      for (int y = y0; y <= y1; ++y) {
        const double dy = lo_.y + (y + 0.5) * h_.y - c.y;
        const double ry2 = rz2 - dy * dy;
        if (ry2 < 0) continue;
        const auto [x0, x1] = range(0, c.x, std::sqrt(ry2));
        if (x0 > x1) continue;
        const std::uint32_t* row =
            &prefix_[(static_cast<std::size_t>(z) * n_[1] + static_cast<std::size_t>(y)) *
                     (static_cast<std::size_t>(n_[0]) + 1)];
        count += row[x1 + 1] - row[x0];
      }
    }
    return count;
  }

 private:
  dvec3 lo_, h_;
  std::array<int, 3> n_{1, 1, 1};
  double voxel_volume_ = 0;
  std::vector<std::uint32_t> prefix_;
  std::vector<dvec3> inside_points_;
};

// Everything a fit needs: the checked mesh, its samples, the inside test and the voxels.
struct Context {
  Prepared mesh;
  SurfaceSampler sampler;
  InsideTester tester;
  explicit Context(const data::MeshData& m) : mesh(prepare(m)), sampler(mesh), tester(mesh) {}
};

float round_up(double r) {
  float f = static_cast<float>(r);
  if (static_cast<double>(f) < r) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// The triangles split at the midpoint of their longest edge until every edge is at most
// `max_edge`.
std::vector<std::array<dvec3, 3>> split_triangles(const Prepared& m, double max_edge) {
  std::vector<std::array<dvec3, 3>> out, stack;
  for (const auto& t : m.tris) {
    stack.push_back(t);
    while (!stack.empty()) {
      const std::array<dvec3, 3> tri = stack.back();
      stack.pop_back();
      int k = 0;
      double longest = 0;
      for (int e = 0; e < 3; ++e) {
        const double l =
            dist2(tri[static_cast<std::size_t>(e)], tri[static_cast<std::size_t>((e + 1) % 3)]);
        if (l > longest) {
          longest = l;
          k = e;
        }
      }
      if (longest <= max_edge * max_edge) {
        out.push_back(tri);
        continue;
      }
      const auto i0 = static_cast<std::size_t>(k), i1 = static_cast<std::size_t>((k + 1) % 3),
                 i2 = static_cast<std::size_t>((k + 2) % 3);
      const dvec3 mid = 0.5 * (tri[i0] + tri[i1]);
      stack.push_back({tri[i0], mid, tri[i2]});
      stack.push_back({mid, tri[i1], tri[i2]});
    }
  }
  return out;
}

// The set from the centres and the members: centres rounded to float, each radius the largest
// member distance from the rounded centre (rounded up), then the surface closed (the header's
// "Closing"). Returns the number of spheres grown.
constexpr double kCloseEdge = 0.02;      // of the box diagonal: the triangles checked
constexpr double kCloseMinEdge = 0.001;  // finest split before a sphere grows

std::size_t finalize(const Prepared& m, const std::vector<dvec3>& pts,
                     const std::vector<dvec3>& centres, const std::vector<int>& owner,
                     std::vector<data::Sphere>& out) {
  out.assign(centres.size(), data::Sphere{});
  std::vector<dvec3> c(centres.size());
  std::vector<double> r(centres.size(), 0);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    out[i].centre = glm::vec3(centres[i]);
    c[i] = dvec3(out[i].centre);
  }
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const auto o = static_cast<std::size_t>(owner[p]);
    r[o] = std::max(r[o], dist2(pts[p], c[o]));
  }
  for (double& v : r) v = std::sqrt(v);
  using Tri = std::array<dvec3, 3>;
  const auto need = [&](const Tri& t, std::size_t s) {
    return std::sqrt(std::max({dist2(t[0], c[s]), dist2(t[1], c[s]), dist2(t[2], c[s])}));
  };
  const auto held = [&](const Tri& t) {
    for (std::size_t s = 0; s < c.size(); ++s)
      if (need(t, s) <= r[s]) return true;
    return false;
  };
  const auto fine = split_triangles(m, kCloseEdge * m.diag);
  std::vector<unsigned char> open(fine.size());
  parallel_for(fine.size(), [&](std::size_t i) { open[i] = held(fine[i]) ? 0 : 1; });
  std::vector<unsigned char> grown(c.size(), 0);
  const double min_edge2 = (kCloseMinEdge * m.diag) * (kCloseMinEdge * m.diag);
  std::vector<Tri> stack;
  for (std::size_t i = 0; i < fine.size(); ++i) {
    if (!open[i]) continue;
    // Split where no single sphere holds a piece; grow only at the finest pieces.
    stack.push_back(fine[i]);
    while (!stack.empty()) {
      const Tri t = stack.back();
      stack.pop_back();
      if (held(t)) continue;
      int k = 0;
      double longest = 0;
      for (int e = 0; e < 3; ++e) {
        const double l =
            dist2(t[static_cast<std::size_t>(e)], t[static_cast<std::size_t>((e + 1) % 3)]);
        if (l > longest) {
          longest = l;
          k = e;
        }
      }
      if (longest > min_edge2) {
        const auto i0 = static_cast<std::size_t>(k), i1 = static_cast<std::size_t>((k + 1) % 3),
                   i2 = static_cast<std::size_t>((k + 2) % 3);
        const dvec3 mid = 0.5 * (t[i0] + t[i1]);
        stack.push_back({t[i0], mid, t[i2]});
        stack.push_back({mid, t[i1], t[i2]});
        continue;
      }
      std::size_t best = 0;
      double growth = std::numeric_limits<double>::max();
      for (std::size_t s = 0; s < c.size(); ++s) {
        const double g = need(t, s) - r[s];
        if (g < growth) {
          growth = g;
          best = s;
        }
      }
      r[best] = need(t, best);
      grown[best] = 1;
    }
  }
  for (std::size_t i = 0; i < c.size(); ++i) {
    out[i].radius = round_up(r[i] * (1 + 1e-6) + 1e-7 * m.diag);
    out[i].parent = -1;
  }
  return static_cast<std::size_t>(std::count(grown.begin(), grown.end(), 1));
}

// k-means++ seeding then Lloyd iterations (see the header). Fills owner; returns the centres.
std::vector<dvec3> kmeans(const std::vector<dvec3>& pts, int k, std::uint64_t seed,
                          std::vector<int>& owner, int& iterations, const Progress& progress,
                          double p0, double p1) {
  const std::size_t n = pts.size();
  const auto K = static_cast<std::size_t>(k);
  std::vector<dvec3> centres;
  centres.reserve(K);
  Rng rng(seed, kSeeding, 0);
  centres.push_back(pts[std::min(n - 1, static_cast<std::size_t>(rng.uniform() * n))]);
  std::vector<double> d2(n);
  parallel_for(n, [&](std::size_t i) { d2[i] = dist2(pts[i], centres[0]); });
  while (centres.size() < K) {
    double total = 0;
    for (double d : d2) total += d;
    std::size_t pick = 0;
    if (total > 0) {
      const double target = rng.uniform() * total;
      double acc = 0;
      for (pick = 0; pick + 1 < n; ++pick) {
        acc += d2[pick];
        if (acc > target && d2[pick] > 0) break;
      }
    } else {
      pick = std::min(n - 1, static_cast<std::size_t>(rng.uniform() * n));
    }
    centres.push_back(pts[pick]);
    const dvec3 c = centres.back();
    parallel_for(n, [&](std::size_t i) { d2[i] = std::min(d2[i], dist2(pts[i], c)); });
  }
  progress(p0 + 0.1 * (p1 - p0), "kmeans");

  owner.assign(n, -1);
  std::vector<int> next(n);
  constexpr int kMaxIterations = 100;
  for (iterations = 1; iterations <= kMaxIterations; ++iterations) {
    parallel_for(n, [&](std::size_t i) {
      int best = 0;
      double bd = dist2(pts[i], centres[0]);
      for (std::size_t c = 1; c < K; ++c) {
        const double d = dist2(pts[i], centres[c]);
        if (d < bd) {
          bd = d;
          best = static_cast<int>(c);
        }
      }
      next[i] = best;
    });
    std::size_t changed = 0;
    for (std::size_t i = 0; i < n; ++i) changed += next[i] != owner[i];
    owner.swap(next);
    if (changed == 0) break;
    std::vector<dvec3> sum(K, dvec3(0));
    std::vector<std::size_t> count(K, 0);
    for (std::size_t i = 0; i < n; ++i) {
      sum[static_cast<std::size_t>(owner[i])] += pts[i];
      ++count[static_cast<std::size_t>(owner[i])];
    }
    for (std::size_t c = 0; c < K; ++c) {
      if (count[c] > 0) {
        centres[c] = sum[c] / static_cast<double>(count[c]);
        continue;
      }
      // Empty: restart at the point farthest from its own centre (in a cluster of two or more).
      std::size_t far = 0;
      double fd = -1;
      for (std::size_t i = 0; i < n; ++i) {
        const auto o = static_cast<std::size_t>(owner[i]);
        if (count[o] < 2) continue;
        const double d = dist2(pts[i], centres[o]);
        if (d > fd) {
          fd = d;
          far = i;
        }
      }
      if (fd < 0) continue;
      --count[static_cast<std::size_t>(owner[far])];
      owner[far] = static_cast<int>(c);
      count[c] = 1;
      centres[c] = pts[far];
    }
    progress(p0 + (p1 - p0) * (0.1 + 0.9 * iterations / kMaxIterations), "kmeans");
  }
  iterations = std::min(iterations, kMaxIterations);
  return centres;
}

// [Guerrero08] sec. 4.1 eq. 1, the Lloyd-style iteration described in the header.
class Variational {
 public:
  Variational(const std::vector<dvec3>& pts, const VoxelGrid& voxels)
      : pts_(pts), voxels_(voxels) {}

  // Outside volume of the ball: V(S) - V(S inside O).
  double cost(const dvec3& c, double r) const {
    return 4.0 / 3.0 * kPi * r * r * r -
           voxels_.voxel_volume() * static_cast<double>(voxels_.count_in_ball(c, r));
  }

  struct Ball {
    dvec3 c{0};
    double r = 0;
    double cost = 0;
  };

  Ball bound(const std::vector<std::uint32_t>& members, const dvec3& c) const {
    double r2 = 0;
    for (std::uint32_t m : members) r2 = std::max(r2, dist2(pts_[m], c));
    const double r = std::sqrt(r2);
    return {c, r, cost(c, r)};
  }

  // Centre of least outside volume for the members (compass search), radius the largest member
  // distance.
  Ball update(const std::vector<std::uint32_t>& members, const dvec3* old_centre) const {
    dvec3 mean(0);
    for (std::uint32_t m : members) mean += pts_[m];
    mean /= static_cast<double>(members.size());
    Ball cur = bound(members, mean);
    if (old_centre != nullptr) {
      const Ball old = bound(members, *old_centre);
      if (old.cost <= cur.cost) cur = old;
    }
    static const std::array<dvec3, 14> kDirs = [] {
      std::array<dvec3, 14> d{};
      int k = 0;
      for (int a = 0; a < 3; ++a)
        for (int s : {-1, 1}) {
          d[static_cast<std::size_t>(k)] = dvec3(0);
          d[static_cast<std::size_t>(k++)][a] = s;
        }
      for (int x : {-1, 1})
        for (int y : {-1, 1})
          for (int z : {-1, 1}) d[static_cast<std::size_t>(k++)] = dvec3(x, y, z) / std::sqrt(3.0);
      return d;
    }();
    const double r0 = cur.r;
    double step = 0.25 * r0;
    for (int evals = 0; step > 1e-3 * r0 && evals < 400;) {
      Ball best = cur;
      for (const dvec3& d : kDirs) {
        const Ball b = bound(members, cur.c + step * d);
        ++evals;
        if (b.cost < best.cost) best = b;
      }
      if (best.cost < cur.cost) {
        cur = best;
      } else {
        step *= 0.5;
      }
    }
    return cur;
  }

 private:
  const std::vector<dvec3>& pts_;
  const VoxelGrid& voxels_;
};

std::vector<dvec3> variational(const std::vector<dvec3>& pts, const VoxelGrid& voxels,
                               std::vector<dvec3> centres, std::vector<int>& owner,
                               int max_iterations, int& iterations, double& best_cost,
                               const Progress& progress, double p0, double p1) {
  const std::size_t n = pts.size(), K = centres.size();
  const Variational fit(pts, voxels);
  std::vector<std::vector<std::uint32_t>> members(K);
  const auto gather = [&] {
    for (auto& m : members) m.clear();
    for (std::size_t i = 0; i < n; ++i)
      members[static_cast<std::size_t>(owner[i])].push_back(static_cast<std::uint32_t>(i));
  };
  gather();
  std::vector<Variational::Ball> balls(K);
  for (std::size_t s = 0; s < K; ++s)
    balls[s] = members[s].empty() ? Variational::Ball{centres[s], 0, 0}
                                  : fit.bound(members[s], centres[s]);
  const auto total = [&] {
    double t = 0;
    for (const auto& b : balls) t += b.cost;
    return t;
  };
  best_cost = total();
  std::vector<dvec3> best_centres = centres;
  std::vector<int> best_owner = owner;
  std::vector<int> next(n);
  double last = best_cost;
  iterations = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    iterations = it;
    // Assignment: the sphere of least |p - c| / r ([Guerrero08] eq. 2). The point's own sphere
    // covers it (d <= 1), so the winner always covers it: only covering spheres are tried.
    parallel_for(n, [&](std::size_t i) {
      int best = owner[i];
      const auto& own = balls[static_cast<std::size_t>(best)];
      // A point sphere (r = 0) gives its point away to any sphere that covers it.
      double bd =
          own.r > 0 ? std::sqrt(dist2(pts[i], own.c)) / own.r : std::numeric_limits<double>::max();
      for (std::size_t s = 0; s < K; ++s) {
        const double d2 = dist2(pts[i], balls[s].c);
        if (balls[s].r <= 0 || d2 > balls[s].r * balls[s].r) continue;
        const double d = std::sqrt(d2) / balls[s].r;
        if (d < bd) {
          bd = d;
          best = static_cast<int>(s);
        }
      }
      next[i] = best;
    });
    owner.swap(next);
    gather();
    // Spheres left empty split the costliest sphere's members by 2-means.
    std::vector<unsigned char> fresh(K, 0);
    bool moved = false;
    for (std::size_t e = 0; e < K; ++e) {
      if (!members[e].empty()) continue;
      std::size_t j = K;
      for (std::size_t s = 0; s < K; ++s)
        if (!fresh[s] && members[s].size() >= 2 && (j == K || balls[s].cost > balls[j].cost)) j = s;
      if (j == K) break;
      const auto& mj = members[j];
      std::uint32_t a = mj[0], b = mj[0];
      for (std::uint32_t m : mj)
        if (dist2(pts[m], balls[j].c) > dist2(pts[a], balls[j].c)) a = m;
      for (std::uint32_t m : mj)
        if (dist2(pts[m], pts[a]) > dist2(pts[b], pts[a])) b = m;
      dvec3 ca = pts[a], cb = pts[b];
      std::vector<std::uint32_t> side_a, side_b;
      for (int k = 0; k < 10; ++k) {
        side_a.clear();
        side_b.clear();
        dvec3 sa(0), sb(0);
        for (std::uint32_t m : mj) {
          if (dist2(pts[m], ca) <= dist2(pts[m], cb)) {
            side_a.push_back(m);
            sa += pts[m];
          } else {
            side_b.push_back(m);
            sb += pts[m];
          }
        }
        if (side_a.empty() || side_b.empty()) break;
        ca = sa / static_cast<double>(side_a.size());
        cb = sb / static_cast<double>(side_b.size());
      }
      if (side_a.empty() || side_b.empty()) continue;
      members[j] = std::move(side_a);
      members[e] = std::move(side_b);
      for (std::uint32_t m : members[e]) owner[m] = static_cast<int>(e);
      fresh[j] = fresh[e] = 1;
      moved = true;
    }
    // Update: per sphere the centre of least outside volume.
    tbb::parallel_for(std::size_t{0}, K, [&](std::size_t s) {
      if (members[s].empty()) {
        balls[s] = {balls[s].c, 0, 0};
        return;
      }
      balls[s] = fit.update(members[s], fresh[s] ? nullptr : &balls[s].c);
    });
    const double t = total();
    if (t < best_cost) {
      best_cost = t;
      for (std::size_t s = 0; s < K; ++s) best_centres[s] = balls[s].c;
      best_owner = owner;
    }
    progress(p0 + (p1 - p0) * it / max_iterations, "variational");
    if (!moved && last - t <= 1e-4 * std::abs(last)) break;
    last = t;
  }
  owner = best_owner;
  return best_centres;
}

// Er by stratified jittered Monte Carlo over the box bounding mesh and spheres; coverage on
// fresh surface samples.
SphereSetError evaluate(const Context& ctx, const std::vector<data::Sphere>& spheres,
                        const SphereFitOptions& options) {
  const Prepared& m = ctx.mesh;
  if (options.eval_samples < 1 || options.coverage_samples < 1)
    throw FitError(m.name, "eval_samples and coverage_samples must be at least 1");
  SphereSetError err;
  dvec3 lo = m.lo, hi = m.hi;
  for (const data::Sphere& s : spheres) {
    lo = glm::min(lo, dvec3(s.centre) - dvec3(s.radius));
    hi = glm::max(hi, dvec3(s.centre) + dvec3(s.radius));
  }
  const dvec3 e = hi - lo;
  const double h = std::cbrt(e.x * e.y * e.z / options.eval_samples);
  std::array<std::size_t, 3> n{};
  for (int a = 0; a < 3; ++a)
    n[static_cast<std::size_t>(a)] = static_cast<std::size_t>(std::max(1L, std::lround(e[a] / h)));
  const dvec3 cell(e.x / static_cast<double>(n[0]), e.y / static_cast<double>(n[1]),
                   e.z / static_cast<double>(n[2]));
  const std::size_t total = n[0] * n[1] * n[2];
  const auto in_union = [&](const dvec3& p, double tol) {
    for (const data::Sphere& s : spheres) {
      const double r = s.radius + tol;
      if (dist2(p, dvec3(s.centre)) <= r * r) return true;
    }
    return false;
  };
  std::vector<std::array<std::size_t, 3>> slab(n[2], {0, 0, 0});  // mesh, union, both
  tbb::parallel_for(std::size_t{0}, n[2], [&](std::size_t z) {
    for (std::size_t y = 0; y < n[1]; ++y)
      for (std::size_t x = 0; x < n[0]; ++x) {
        const std::size_t i = (z * n[1] + y) * n[0] + x;
        Rng rng(options.seed, kEval, i);
        const dvec3 p =
            lo + (dvec3(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) +
                  dvec3(rng.uniform(), rng.uniform(), rng.uniform())) *
                     cell;
        const bool a = ctx.tester.inside(p), b = in_union(p, 0);
        slab[z][0] += a;
        slab[z][1] += b;
        slab[z][2] += a && b;
      }
  });
  std::array<std::size_t, 3> count{0, 0, 0};
  for (const auto& s : slab)
    for (int k = 0; k < 3; ++k)
      count[static_cast<std::size_t>(k)] += s[static_cast<std::size_t>(k)];
  const double box = e.x * e.y * e.z;
  err.eval_samples = total;
  err.mesh_volume = box * static_cast<double>(count[0]) / static_cast<double>(total);
  err.union_volume = box * static_cast<double>(count[1]) / static_cast<double>(total);
  if (count[0] == 0) throw FitError(m.name, "no Monte Carlo sample inside the mesh");
  err.outside_volume_ratio = static_cast<double>(count[1]) / static_cast<double>(count[0]) - 1.0;
  err.volume_coverage = static_cast<double>(count[2]) / static_cast<double>(count[0]);

  const auto cov = ctx.sampler.samples(static_cast<std::size_t>(options.coverage_samples),
                                       options.seed, kCoverage);
  std::vector<unsigned char> covered(cov.size());
  const double tol = 1e-6 * m.diag;
  parallel_for(cov.size(), [&](std::size_t i) { covered[i] = in_union(cov[i], tol) ? 1 : 0; });
  std::size_t c = 0;
  for (unsigned char v : covered) c += v;
  err.coverage_samples = cov.size();
  err.coverage = static_cast<double>(c) / static_cast<double>(cov.size());
  return err;
}

}  // namespace

data::MeshData merge_instances(const Model& model) {
  data::MeshData out;
  out.name = model.source;
  for (const Model::Instance& inst : model.instances) {
    const data::MeshData& mesh = *model.meshes.at(inst.mesh);
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (const glm::vec3& p : mesh.positions)
      out.positions.push_back(glm::vec3(inst.world * glm::vec4(p, 1.0f)));
    for (std::uint32_t i : mesh.indices) out.indices.push_back(base + i);
  }
  return out;
}

SphereFitResult fit_spheres(const data::MeshData& mesh, const SphereFitOptions& options) {
  const auto t0 = Clock::now();
  const Progress progress{&options.progress};
  const std::string name = mesh.name.empty() ? std::string("mesh") : mesh.name;
  if (options.count < 1)
    throw FitError(name, "sphere count " + std::to_string(options.count) + ": at least 1");
  if (options.count > kMaxFitSpheres)
    throw FitError(name, "sphere count " + std::to_string(options.count) + ": at most " +
                             std::to_string(kMaxFitSpheres));
  if (options.method != SphereFitMethod::kKMeans && options.method != SphereFitMethod::kVariational)
    throw FitError(name,
                   std::string("unknown fit method ") + sphere_fit_method_name(options.method));
  if (options.surface_samples < 1 || options.volume_cells < 1 || options.max_iterations < 0)
    throw FitError(name, "surface_samples and volume_cells must be at least 1");
  progress(0, "sampling");
  const Context ctx(mesh);
  const Prepared& m = ctx.mesh;

  std::vector<dvec3> pts = ctx.sampler.samples(static_cast<std::size_t>(options.surface_samples),
                                               options.seed, kSurface);
  pts.insert(pts.end(), m.used_vertices.begin(), m.used_vertices.end());
  const std::size_t surface_points = pts.size();
  progress(0.05, "sampling");
  const VoxelGrid voxels(m, ctx.tester, options.volume_cells, options.seed);
  const auto& inside = voxels.inside_points();
  if (inside.size() < 8)
    throw FitError(m.name, "the surface encloses no volume (" + std::to_string(inside.size()) +
                               " of " + std::to_string(voxels.cells()) +
                               " voxels inside by ray parity): open or flat mesh");
  {
    const std::size_t probes = std::min<std::size_t>(256, inside.size());
    std::vector<unsigned char> ok(probes);
    parallel_for(probes, [&](std::size_t k) {
      ok[k] = winding_number(m, inside[k * inside.size() / probes]) >= 0.5 ? 1 : 0;
    });
    std::size_t good = 0;
    for (unsigned char v : ok) good += v;
    if (2 * good < probes)
      throw FitError(m.name, "the surface encloses no volume (winding number below 1/2 at " +
                                 std::to_string(probes - good) + " of " + std::to_string(probes) +
                                 " points ray parity calls inside): open mesh");
  }
  pts.insert(pts.end(), inside.begin(), inside.end());
  if (static_cast<std::size_t>(options.count) > pts.size())
    throw FitError(m.name, "sphere count " + std::to_string(options.count) + " exceeds the " +
                               std::to_string(pts.size()) + " fitting samples");
  progress(0.15, "sampling");

  SphereFitResult result;
  result.method = options.method;
  result.surface_points = surface_points;
  result.volume_points = inside.size();
  std::vector<int> owner;
  int kmeans_iterations = 0;
  const bool var = options.method == SphereFitMethod::kVariational;
  std::vector<dvec3> centres = kmeans(pts, options.count, options.seed, owner, kmeans_iterations,
                                      progress, 0.15, var ? 0.45 : 0.85);
  result.iterations = kmeans_iterations;
  if (var) {
    double best_cost = 0;
    centres = variational(pts, voxels, std::move(centres), owner, options.max_iterations,
                          result.iterations, best_cost, progress, 0.45, 0.85);
  }
  result.grown_spheres = finalize(m, pts, centres, owner, result.spheres);
  const Variational cost(pts, voxels);
  for (const data::Sphere& s : result.spheres)
    result.outside_volume_sum += cost.cost(dvec3(s.centre), s.radius);
  progress(0.85, "evaluating");
  result.error = evaluate(ctx, result.spheres, options);
  progress(1, "evaluating");
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

SphereSetError evaluate_sphere_set(const data::MeshData& mesh,
                                   const std::vector<data::Sphere>& spheres,
                                   const SphereFitOptions& options) {
  const Context ctx(mesh);
  return evaluate(ctx, spheres, options);
}

SphereSetFile to_sphere_file(const SphereFitResult& fit, std::string source_model) {
  SphereSetFile f;
  f.spheres = fit.spheres;
  f.method = fit.method;
  f.outside_volume_ratio = fit.error.outside_volume_ratio;
  f.coverage = fit.error.coverage;
  f.source_model = std::move(source_model);
  return f;
}

}  // namespace penumbra::assets
