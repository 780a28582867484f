#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "penumbra/data/finite.h"
#include "penumbra/systems/probe_cloud/cell_weights.h"

namespace penumbra::probe_cloud {
namespace {

constexpr std::size_t kMaxGridCells = std::size_t{1} << 21;
constexpr float kVertexSnap = 1e-6f;  // a weight this close to 1 is that probe exactly

using data::finite;

std::string vec_str(const glm::vec3& p) {
  return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")";
}

float min_weight(const std::array<float, 4>& w) {
  return std::min(std::min(w[0], w[1]), std::min(w[2], w[3]));
}

// cell_weights() with the inner tetrahedra inline from the hot copy of the transform (the walk's
// hot path; same formula and operations as cell_weights on data/probe_cloud.h's transform).
std::array<float, 4> weights_at(const data::ProbeCloud& cloud, const detail::ProbeHotData& hot,
                                std::int32_t cell, const glm::vec3& p) {
  const auto i = static_cast<std::size_t>(cell);
  if (i < cloud.inner_count) {
    const std::array<float, 12>& m = hot.cells[i].transform;
    const glm::vec3 d = p - glm::vec3(m[9], m[10], m[11]);
    const glm::vec3 l = glm::vec3(m[0], m[1], m[2]) * d.x + glm::vec3(m[3], m[4], m[5]) * d.y +
                        glm::vec3(m[6], m[7], m[8]) * d.z;
    return {l.x, l.y, l.z, 1.0f - l.x - l.y - l.z};
  }
  return cell_weights(cloud, static_cast<std::uint32_t>(cell), p);
}

bool any_nan(const std::array<float, 4>& w) {
  return std::isnan(w[0]) || std::isnan(w[1]) || std::isnan(w[2]) || std::isnan(w[3]);
}

// The result for p in `cell` with its raw weights `w`: convex, snapped to a probe when p is on it.
ProbeWalkResult finish(const detail::ProbeHotData& hot, std::int32_t cell,
                       const std::array<float, 4>& w, const glm::vec3& p) {
  ProbeWalkResult r;
  r.cell = cell;
  r.probes = hot.cells[static_cast<std::size_t>(cell)].vertices;
  r.weights = convex_weights(w);
  if (r.probes[3] == data::kOuterVertex) r.weights[3] = 0;  // an outer cell: weight 3 is 0
  for (std::size_t k = 0; k < 4; ++k) {
    bool at_probe = r.weights[k] >= 1.0f - kVertexSnap;
    if (!at_probe && r.probes[k] >= 0) {
      const float* q = hot.probe(static_cast<std::size_t>(r.probes[k])) + hot.sh_count;
      at_probe = glm::vec3(q[0], q[1], q[2]) == p;
    }
    if (at_probe) {
      r.weights = {0, 0, 0, 0};
      r.weights[k] = 1.0f;
      break;
    }
  }
  return r;
}

// Memory for the hot copy: line-aligned; from 1 MiB on, whole 2 MiB pages advised huge.
std::shared_ptr<void> hot_alloc(std::size_t bytes) {
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  const bool huge = bytes >= (std::size_t{1} << 20);
  const std::size_t align = huge ? kHuge : 64;
  const std::size_t size = (std::max<std::size_t>(bytes, 1) + align - 1) / align * align;
  void* p = std::aligned_alloc(align, size);
  if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  if (huge) (void)madvise(p, size, MADV_HUGEPAGE);  // advice only: 4 KiB pages otherwise
#endif
  std::memset(p, 0, size);
  return std::shared_ptr<void>(p, [](void* q) { std::free(q); });
}

detail::ProbeHotData make_hot(const data::ProbeCloud& c) {
  detail::ProbeHotData h;
  h.sh_count = c.coeffs_per_probe();
  h.stride = (h.sh_count + 3 + 15) / 16 * 16;
  const std::size_t cell_bytes = c.cells.size() * sizeof(detail::ProbeHotCell);
  const std::size_t probe_bytes = c.probe_count() * h.stride * sizeof(float);
  std::shared_ptr<void> memory = hot_alloc(cell_bytes + probe_bytes);
  auto* cells = static_cast<detail::ProbeHotCell*>(memory.get());
  auto* probes = reinterpret_cast<float*>(static_cast<char*>(memory.get()) + cell_bytes);
  for (std::size_t i = 0; i < c.cells.size(); ++i) {
    detail::ProbeHotCell& hc = *new (cells + i) detail::ProbeHotCell{};
    hc.vertices = c.cells[i].vertices;
    if (i >= c.inner_count) continue;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 3; ++row)
        hc.transform[static_cast<std::size_t>(col * 3 + row)] = c.transforms[i][col][row];
  }
  for (std::size_t k = 0; k < c.probe_count(); ++k) {
    float* r = probes + k * h.stride;
    std::copy(c.probe_sh(k), c.probe_sh(k) + h.sh_count, r);
    r[h.sh_count] = c.positions[k].x;
    r[h.sh_count + 1] = c.positions[k].y;
    r[h.sh_count + 2] = c.positions[k].z;
  }
  h.cells = cells;
  h.probes = probes;
  h.memory = std::move(memory);
  return h;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

ProbeCellGrid::ProbeCellGrid(const data::ProbeCloud& cloud) {
  const std::size_t inner = cloud.inner_count;
  if (inner == 0) return;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t t = 0; t < inner; ++t)
    for (std::int32_t v : cloud.cells[t].vertices) {
      lo = glm::min(lo, cloud.positions[static_cast<std::size_t>(v)]);
      hi = glm::max(hi, cloud.positions[static_cast<std::size_t>(v)]);
    }
  const glm::vec3 extent = hi - lo;
  const float largest = std::max({extent.x, extent.y, extent.z});
  const glm::vec3 e = glm::max(extent, glm::vec3(largest * 1e-3f));
  const double target =
      std::clamp<double>(static_cast<double>(inner) / 2.0, 1.0, static_cast<double>(kMaxGridCells));
  float size = static_cast<float>(std::cbrt(double(e.x) * e.y * e.z / target));
  auto count = [&](float ext) {
    return std::clamp(static_cast<int>(std::ceil(ext / size)), 1, 1 << 11);
  };
  for (;;) {
    nx_ = count(e.x);
    ny_ = count(e.y);
    nz_ = count(e.z);
    if (std::size_t(nx_) * std::size_t(ny_) * std::size_t(nz_) <= kMaxGridCells) break;
    size *= 1.25f;
  }
  origin_ = lo;
  const glm::vec3 cell(extent.x / static_cast<float>(nx_), extent.y / static_cast<float>(ny_),
                       extent.z / static_cast<float>(nz_));
  cell_size_ = std::max({cell.x, cell.y, cell.z});
  inv_size_ = glm::vec3(cell.x > 0 ? 1.0f / cell.x : 0.0f, cell.y > 0 ? 1.0f / cell.y : 0.0f,
                        cell.z > 0 ? 1.0f / cell.z : 0.0f);
  const std::size_t n = std::size_t(nx_) * std::size_t(ny_) * std::size_t(nz_);
  start_.assign(n, kNoCell);
  std::vector<float> best(n, std::numeric_limits<float>::max());
  auto index_of = [&](float x, float o, float inv, int nmax) {
    return std::clamp(static_cast<int>((x - o) * inv), 0, nmax - 1);
  };
  for (std::size_t t = 0; t < inner; ++t) {
    glm::vec3 tlo(std::numeric_limits<float>::max()), thi(-std::numeric_limits<float>::max());
    glm::vec3 centroid(0.0f);
    for (std::int32_t v : cloud.cells[t].vertices) {
      const glm::vec3& q = cloud.positions[static_cast<std::size_t>(v)];
      tlo = glm::min(tlo, q);
      thi = glm::max(thi, q);
      centroid += 0.25f * q;
    }
    const int x0 = index_of(tlo.x, lo.x, inv_size_.x, nx_),
              x1 = index_of(thi.x, lo.x, inv_size_.x, nx_);
    const int y0 = index_of(tlo.y, lo.y, inv_size_.y, ny_),
              y1 = index_of(thi.y, lo.y, inv_size_.y, ny_);
    const int z0 = index_of(tlo.z, lo.z, inv_size_.z, nz_),
              z1 = index_of(thi.z, lo.z, inv_size_.z, nz_);
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const glm::vec3 centre = lo + (glm::vec3(x, y, z) + 0.5f) * cell;
          const glm::vec3 d = centre - centroid;
          const float d2 = glm::dot(d, d);
          const std::size_t g =
              (std::size_t(z) * std::size_t(ny_) + std::size_t(y)) * std::size_t(nx_) +
              std::size_t(x);
          if (d2 < best[g]) {
            best[g] = d2;
            start_[g] = static_cast<std::int32_t>(t);
          }
        }
  }
  // Grid cells no box overlaps (outside the hull) take a neighbour's tetrahedron (BFS).
  std::vector<std::size_t> frontier, next;
  for (std::size_t g = 0; g < n; ++g)
    if (start_[g] != kNoCell) frontier.push_back(g);
  while (!frontier.empty()) {
    next.clear();
    for (std::size_t g : frontier) {
      const int x = static_cast<int>(g % std::size_t(nx_));
      const int y = static_cast<int>((g / std::size_t(nx_)) % std::size_t(ny_));
      const int z = static_cast<int>(g / (std::size_t(nx_) * std::size_t(ny_)));
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                            {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= nx_ || q[1] < 0 || q[1] >= ny_ || q[2] < 0 || q[2] >= nz_) continue;
        const std::size_t h =
            (std::size_t(q[2]) * std::size_t(ny_) + std::size_t(q[1])) * std::size_t(nx_) +
            std::size_t(q[0]);
        if (start_[h] != kNoCell) continue;
        start_[h] = start_[g];
        next.push_back(h);
      }
    }
    frontier.swap(next);
  }
}

std::int32_t ProbeCellGrid::start_cell(const glm::vec3& p) const {
  if (start_.empty()) return kNoCell;
  auto idx = [](float x, float o, float inv, int n) {
    const float f = (x - o) * inv;  // clamp in float first: no overflow converting to int
    return std::clamp(static_cast<int>(std::clamp(f, 0.0f, static_cast<float>(n - 1))), 0, n - 1);
  };
  const int x = idx(p.x, origin_.x, inv_size_.x, nx_);
  const int y = idx(p.y, origin_.y, inv_size_.y, ny_);
  const int z = idx(p.z, origin_.z, inv_size_.z, nz_);
  return start_[(std::size_t(z) * std::size_t(ny_) + std::size_t(y)) * std::size_t(nx_) +
                std::size_t(x)];
}

// ---------------------------------------------------------------------------------------------

ProbeTetWalk::ProbeTetWalk(std::shared_ptr<const data::ProbeCloud> cloud,
                           const ProbeWalkSettings& settings)
    : cloud_(std::move(cloud)), settings_(settings) {
  if (!cloud_) throw std::invalid_argument("ProbeTetWalk: the cloud is null");
  const data::ProbeCloud& c = *cloud_;
  const std::string what = "ProbeTetWalk: invalid probe cloud: ";
  if (settings_.max_steps < 1 || !(settings_.far_cells > 0))
    throw std::invalid_argument("ProbeTetWalk: max_steps must be >= 1 and far_cells > 0");
  if (c.bands < data::kProbeMinBands || c.bands > data::kProbeMaxBands)
    throw std::invalid_argument(what + "bands = " + std::to_string(c.bands) + " (2..4)");
  if (c.sh.size() != c.probe_count() * c.coeffs_per_probe())
    throw std::invalid_argument(what + "sh has " + std::to_string(c.sh.size()) + " floats, " +
                                std::to_string(c.probe_count()) + " probes need " +
                                std::to_string(c.probe_count() * c.coeffs_per_probe()));
  if (c.transforms.size() != c.cells.size())
    throw std::invalid_argument(what + "transforms has " + std::to_string(c.transforms.size()) +
                                " entries for " + std::to_string(c.cells.size()) + " cells");
  if (c.inner_count > c.cells.size())
    throw std::invalid_argument(what + "inner_count " + std::to_string(c.inner_count) +
                                " > cells " + std::to_string(c.cells.size()));
  if (c.inner_count < c.cells.size() && c.hull_normals.size() != c.probe_count())
    throw std::invalid_argument(what + "outer cells need one hull normal per probe");
  const auto probes = static_cast<std::int32_t>(c.probe_count());
  const auto cells = static_cast<std::int64_t>(c.cells.size());
  for (std::size_t i = 0; i < c.cells.size(); ++i) {
    const data::ProbeCell& cell = c.cells[i];
    const bool outer = i >= c.inner_count;
    if (cell.outer() != outer)
      throw std::invalid_argument(
          what + "cell " + std::to_string(i) +
          (outer ? " is past inner_count but not outer" : " is outer but before inner_count"));
    for (int k = 0; k < (outer ? 3 : 4); ++k) {
      const std::int32_t v = cell.vertices[static_cast<std::size_t>(k)];
      if (v < 0 || v >= probes)
        throw std::invalid_argument(what + "cell " + std::to_string(i) + ": vertex " +
                                    std::to_string(v) + " out of range");
    }
    for (std::int32_t nb : cell.neighbours)
      if (nb < -1 || nb >= cells)
        throw std::invalid_argument(what + "cell " + std::to_string(i) + ": neighbour " +
                                    std::to_string(nb) + " out of range");
  }
  for (std::size_t i = 0; i < c.positions.size(); ++i)
    if (!finite(c.positions[i]))
      throw std::invalid_argument(what + "probe " + std::to_string(i) + " is not finite");
  grid_ = ProbeCellGrid(c);
  hot_ = make_hot(c);
  cell_count_ = c.cells.size();
}

ProbeWalkResult ProbeTetWalk::walk(const glm::vec3& p, std::int32_t start, int cap, float far2,
                                   bool& done, std::vector<std::int32_t>* path) const {
  const data::ProbeCloud& c = *cloud_;
  constexpr int kRing = 64;  // the visited check looks at the last 64 cells
  std::array<std::int32_t, kRing> visited;
  int count = 0;
  auto seen = [&](std::int32_t cell) {
    const int n = std::min(count, kRing);
    for (int i = 0; i < n; ++i)
      if (visited[static_cast<std::size_t>(i)] == cell) return true;
    return false;
  };
  std::int32_t cell = start, best_cell = kNoCell;
  float best_min = -std::numeric_limits<float>::infinity();
  std::array<float, 4> best_w{};
  done = false;
  for (int steps = 0;; ++steps) {
    visited[static_cast<std::size_t>(count++ % kRing)] = cell;
    if (path) path->push_back(cell);
    const std::array<float, 4> w = weights_at(c, hot_, cell, p);
    ProbeWalkResult r;
    r.steps = steps;
    if (any_nan(w)) return r;  // a degenerate cell: let the caller fall back
    const float mn = min_weight(w);
    if (mn >= -kInsideTolerance) {
      r = finish(hot_, cell, w, p);
      r.steps = steps;
      done = true;
      return r;
    }
    if (steps == 0 && far2 >= 0) {
      // A teleport: p far from every vertex of the start cell; the grid's start is nearer.
      // (The positions from the hot probe records: the batch loops prefetched them.)
      const std::array<std::int32_t, 4>& v = hot_.cells[static_cast<std::size_t>(cell)].vertices;
      float nearest = std::numeric_limits<float>::infinity();
      for (std::size_t k = 0; k < (v[3] == data::kOuterVertex ? 3u : 4u); ++k) {
        const float* q = hot_.probe(static_cast<std::size_t>(v[k])) + hot_.sh_count;
        const glm::vec3 d = p - glm::vec3(q[0], q[1], q[2]);
        nearest = std::min(nearest, glm::dot(d, d));
      }
      if (nearest > far2) return r;
    }
    if (mn > best_min) {
      best_min = mn;
      best_cell = cell;
      best_w = w;
    }
    if (steps >= cap) return r;
    // [Sukys14] sec. 3.2: across the face of the most negative weight (the next one when that
    // neighbour was visited on this walk: a cycle from round-off).
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return w[static_cast<std::size_t>(a)] < w[static_cast<std::size_t>(b)];
    });
    std::int32_t next = kNoCell;
    for (int k : order) {
      if (!(w[static_cast<std::size_t>(k)] < -kInsideTolerance)) break;
      const std::int32_t nb =
          c.cells[static_cast<std::size_t>(cell)].neighbours[static_cast<std::size_t>(k)];
      if (nb >= 0 && !seen(nb)) {
        next = nb;
        break;
      }
    }
    if (next == kNoCell) {
      // Every way out leads back: p sits on faces the cells disagree about by round-off. The
      // visited cell closest to holding p, unless even that one is clearly off (then fall back).
      if (best_min < -1e-3f) return r;
      r = finish(hot_, best_cell, best_w, p);
      r.steps = steps;
      done = true;
      return r;
    }
    cell = next;
  }
}

ProbeWalkResult ProbeTetWalk::brute_force(const glm::vec3& p) const {
  const data::ProbeCloud& c = *cloud_;
  std::int32_t best_cell = kNoCell;
  float best_min = -std::numeric_limits<float>::infinity();
  std::array<float, 4> best_w{};
  for (std::size_t i = 0; i < c.cells.size(); ++i) {
    const std::array<float, 4> w = weights_at(c, hot_, static_cast<std::int32_t>(i), p);
    if (any_nan(w)) continue;
    const float mn = min_weight(w);
    if (mn > best_min) {
      best_min = mn;
      best_cell = static_cast<std::int32_t>(i);
      best_w = w;
    }
  }
  if (best_cell == kNoCell) return no_cells(p);
  return finish(hot_, best_cell, best_w, p);
}

ProbeWalkResult ProbeTetWalk::no_cells(const glm::vec3& p) const {
  const data::ProbeCloud& c = *cloud_;
  ProbeWalkResult r;
  r.fallback = true;
  if (c.positions.empty()) return r;
  std::size_t nearest = 0;
  float best = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < c.positions.size(); ++i) {
    const glm::vec3 d = c.positions[i] - p;
    const float d2 = glm::dot(d, d);
    if (d2 < best) {
      best = d2;
      nearest = i;
    }
  }
  r.probes[0] = static_cast<std::int32_t>(nearest);
  r.weights[0] = 1.0f;
  return r;
}

ProbeWalkResult ProbeTetWalk::locate(const glm::vec3& p, std::int32_t start,
                                     std::vector<std::int32_t>* path) const {
  if (!finite(p))
    throw std::invalid_argument("ProbeTetWalk::locate: the point " + vec_str(p) + " is not finite");
  const data::ProbeCloud& c = *cloud_;
  if (c.inner_count == 0) return no_cells(p);
  const auto cells = static_cast<std::int64_t>(c.cells.size());
  if (start >= 0 && start < static_cast<std::int64_t>(c.inner_count)) {
    // The common case inline (a cached tetrahedron that still holds p: about 7 entities in 8
    // moving 8 cm a frame): walk()'s first step without its bookkeeping, the same result.
    const std::array<float, 4> w = weights_at(c, hot_, start, p);
    if (!any_nan(w) && min_weight(w) >= -kInsideTolerance) {
      if (path) path->push_back(start);
      return finish(hot_, start, w, p);
    }
  }
  int steps = 0;
  bool done = false;
  if (start >= 0 && start < cells) {
    const float far = settings_.far_cells * grid_.cell_size();
    ProbeWalkResult r = walk(p, start, settings_.max_steps, far * far, done, path);
    if (done) return r;
    steps = r.steps;
  }
  const int cap = std::max(4 * settings_.max_steps, 1024);
  ProbeWalkResult r = walk(p, grid_.start_cell(p), cap, -1.0f, done, path);
  if (!done) {
    steps += r.steps;
    r = brute_force(p);
    if (path) path->push_back(r.cell);
  }
  r.steps += steps;
  r.fallback = true;
  return r;
}

ProbeWalkResult ProbeTetWalk::at(std::int32_t cell, const glm::vec3& p) const {
  const data::ProbeCloud& c = *cloud_;
  if (cell < 0 || static_cast<std::size_t>(cell) >= c.cells.size()) return no_cells(p);
  return finish(hot_, cell, weights_at(c, hot_, cell, p), p);
}

namespace {
// The probes' SH weighted into out (kIn: the cloud's coefficients per channel; kOut: out's):
// accumulated in a local array of min(kIn, kOut) coefficients per channel (one contiguous block
// when kIn == kOut: 27 floats for 3 bands), then stored, zero past the cloud's bands.
// Probe k's SH at base + k * stride (the cloud's sh, or the walk's hot records).
template <std::size_t kIn, std::size_t kOut>
void accumulate(const float* base, std::size_t stride, const std::array<std::int32_t, 4>& probes,
                const std::array<float, 4>& weights, std::array<std::array<float, kOut>, 3>& out) {
  constexpr std::size_t kN = std::min<std::size_t>(kIn, kOut);
  std::array<float, 3 * kN> acc{};
  for (std::size_t k = 0; k < 4; ++k) {
    const float w = weights[k];
    if (probes[k] < 0 || w == 0.0f) continue;
    const float* s = base + static_cast<std::size_t>(probes[k]) * stride;
    if constexpr (kN == kIn) {
      for (std::size_t i = 0; i < 3 * kN; ++i) acc[i] += w * s[i];
    } else {
      for (std::size_t ch = 0; ch < 3; ++ch)
        for (std::size_t i = 0; i < kN; ++i) acc[ch * kN + i] += w * s[ch * kIn + i];
    }
  }
  for (std::size_t ch = 0; ch < 3; ++ch)
    for (std::size_t i = 0; i < kOut; ++i) out[ch][i] = i < kN ? acc[ch * kN + i] : 0.0f;
}

template <std::size_t kOut>  // out: sh::CoeffsRgb<bands>, kOut = bands^2
void interpolate_at(int bands, const float* base, std::size_t stride,
                    const std::array<std::int32_t, 4>& probes, const std::array<float, 4>& weights,
                    std::array<std::array<float, kOut>, 3>& out) {
  switch (bands) {  // the coefficient count as a constant: unrolled, vectorised loops
    case 2:
      accumulate<4>(base, stride, probes, weights, out);
      break;
    case 3:
      accumulate<9>(base, stride, probes, weights, out);
      break;
    case 4:
      accumulate<16>(base, stride, probes, weights, out);
      break;
    default:
      throw std::invalid_argument("interpolate_probe_sh: the cloud has " + std::to_string(bands) +
                                  " bands (2..4)");
  }
}
template <std::size_t kOut>
void interpolate_at(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                    const std::array<float, 4>& weights,
                    std::array<std::array<float, kOut>, 3>& out) {
  interpolate_at(cloud.bands, cloud.sh.data(), cloud.coeffs_per_probe(), probes, weights, out);
}
}  // namespace

ProbeSh interpolate_probe_sh(const data::ProbeCloud& cloud,
                             const std::array<std::int32_t, 4>& probes,
                             const std::array<float, 4>& weights) {
  ProbeSh out;
  interpolate_at(cloud, probes, weights, out);
  return out;
}

void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, sh::CoeffsRgb<2>& out) {
  interpolate_at(cloud, probes, weights, out);
}
void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, sh::CoeffsRgb<3>& out) {
  interpolate_at(cloud, probes, weights, out);
}
void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, ProbeSh& out) {
  interpolate_at(cloud, probes, weights, out);
}

ProbeSh ProbeTetWalk::interpolate(const ProbeWalkResult& r) const {
  ProbeSh out;
  interpolate_at(cloud_->bands, hot_.probes, hot_.stride, r.probes, r.weights, out);
  return out;
}
void ProbeTetWalk::interpolate(const ProbeWalkResult& r, sh::CoeffsRgb<2>& out) const {
  interpolate_at(cloud_->bands, hot_.probes, hot_.stride, r.probes, r.weights, out);
}
void ProbeTetWalk::interpolate(const ProbeWalkResult& r, sh::CoeffsRgb<3>& out) const {
  interpolate_at(cloud_->bands, hot_.probes, hot_.stride, r.probes, r.weights, out);
}
void ProbeTetWalk::interpolate(const ProbeWalkResult& r, ProbeSh& out) const {
  interpolate_at(cloud_->bands, hot_.probes, hot_.stride, r.probes, r.weights, out);
}

template <int kOutBands>
std::size_t ProbeTetWalk::batch(std::span<const glm::vec3> points, std::span<std::int32_t> cells,
                                std::span<sh::CoeffsRgb<kOutBands>> out) const {
  if (cells.size() != points.size() || out.size() != points.size())
    throw std::invalid_argument("ProbeTetWalk::locate_batch: " + std::to_string(points.size()) +
                                " points, " + std::to_string(cells.size()) + " cells, " +
                                std::to_string(out.size()) + " outputs (must be equal)");
  std::size_t fallbacks = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i + kPrefetchCells < points.size()) prefetch(cells[i + kPrefetchCells], false);
    if (i + kPrefetchProbes < points.size()) prefetch(cells[i + kPrefetchProbes], true);
    const ProbeWalkResult r = locate(points[i], cells[i]);
    cells[i] = r.cell;
    interpolate_at(cloud_->bands, hot_.probes, hot_.stride, r.probes, r.weights, out[i]);
    fallbacks += r.fallback ? 1 : 0;
  }
  return fallbacks;
}

std::size_t ProbeTetWalk::locate_batch(std::span<const glm::vec3> points,
                                       std::span<std::int32_t> cells,
                                       std::span<ProbeSh> out) const {
  return batch<kProbeShBands>(points, cells, out);
}
std::size_t ProbeTetWalk::locate_batch(std::span<const glm::vec3> points,
                                       std::span<std::int32_t> cells,
                                       std::span<sh::CoeffsRgb<3>> out) const {
  return batch<3>(points, cells, out);
}
std::size_t ProbeTetWalk::locate_batch(std::span<const glm::vec3> points,
                                       std::span<std::int32_t> cells,
                                       std::span<sh::CoeffsRgb<2>> out) const {
  return batch<2>(points, cells, out);
}

}  // namespace penumbra::probe_cloud
