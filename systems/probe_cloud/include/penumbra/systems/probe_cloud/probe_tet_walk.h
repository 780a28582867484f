// Point location in a probe cloud (data/probe_cloud.h) and the interpolation of its probes' SH.
// No ECS here: the traversal system (probe_systems.h), the tests and the benchmarks drive it.
//
// The walk ([Sukys14] sec. 3.2, "Traversal"): from a start cell (an entity's cached cell), take
// the cell's weights at p (cell_weights.h); when all are >= -kInsideTolerance p is in the cell,
// else step to the neighbour across the face of the most negative weight. Outside the hull the
// walk enters the outer cells ([Cupisz12]) and ends in one of them. Guards:
//  - a visited check: a step into a cell already on this walk's path (a cycle, from float
//    round-off near degenerate faces) takes the next most negative face instead; when every
//    negative face leads back, the walk ends in the visited cell that came closest to holding p
//    (largest smallest weight) and its clamped weights, or, when even that one's smallest weight
//    is below -1e-3, the fallback runs; a neighbour link of -1 (not in a valid cloud) is a wall;
//  - a step cap (ProbeWalkSettings::max_steps): past it, the fallback locate runs;
//  - the fallback locate also runs when the start is invalid (-1, out of range) or, p not being in
//    the start cell, p is farther than ProbeWalkSettings::far_cells grid cells from every vertex
//    of the start cell (a teleport; inner and outer start cells alike):
//    a uniform grid over the inner cells' bounding boxes (ProbeCellGrid, built once per cloud)
//    gives an inner tetrahedron near p (p clamped into the grid), and the walk goes on from there
//    with a cap of max(4 * max_steps, 1024); should that fail too, every cell is tested
//    (linear, never seen in the tests).
// A start cell from another cloud that is in range cannot be told apart here: it only costs
// steps (the far check or the cap sends it to the fallback). The system keeps the cloud's
// generation beside each cached cell for that (probe_systems.h).
//
// A weight within 1e-6 of 1, or p equal to a probe's position, gives that probe weight 1 exactly
// (interpolation at a probe returns its SH bit for bit).
//
// Clouds without cells (0-3 probes, or all coplanar/collinear: inner_count == 0): the nearest
// probe, weight 1 (a linear search over the probes); 0 probes: no probe, zero SH. Result::cell
// is then -1 and Result::fallback true.
//
// Non-finite p: locate() throws std::invalid_argument (the system checks first and names the
// entity). Threading: a ProbeTetWalk is immutable after construction; locate() and the
// interpolation functions are const and pure, safe from any number of threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/probe_cloud.h"
#include "penumbra/sh/basis.h"

namespace penumbra::probe_cloud {

inline constexpr std::int32_t kNoCell = -1;
// A weight >= -kInsideTolerance counts as inside (p on a face, edge or vertex within round-off).
inline constexpr float kInsideTolerance = 1e-5f;
// Interpolated SH are returned with 4 bands (16 coefficients per channel), zero-padded past the
// cloud's bands (the coefficient index l(l+1)+m does not depend on the band count).
inline constexpr int kProbeShBands = data::kProbeMaxBands;
using ProbeSh = sh::CoeffsRgb<kProbeShBands>;

// How far ahead batch loops (locate_batch, probes.walk) hint the cache with prefetch(): the
// cells and transforms 8 points ahead, the probes' SH 4 ahead.
inline constexpr std::size_t kPrefetchCells = 16;
inline constexpr std::size_t kPrefetchProbes = 8;

namespace detail {
// The walk's own copy of what an entity's locate + interpolation reads (ProbeTetWalk builds it
// once per cloud): one 64-byte line per cell (an inner cell's transform columns 0..3, xyz each:
// T^-1 and p3; the cell's four probes), and one record per probe (its 3 bands^2 SH floats, then
// its position, padded to whole lines: 128 bytes at 3 bands), both aligned to lines and, when
// large, to 2 MiB pages advised huge (madvise). The cloud's own arrays put a cell test on 2-4
// lines (ProbeCell 32 bytes + mat4 64, 16-byte aligned) and a probe on 3-4 (108 bytes of SH
// anywhere in the array, its position in another); each was also a TLB miss on 4 KiB pages.
struct alignas(64) ProbeHotCell {
  std::array<float, 12> transform{};       // columns 0..3 of the transform, xyz (inner cells)
  std::array<std::int32_t, 4> vertices{};  // as ProbeCell::vertices
};
static_assert(sizeof(ProbeHotCell) == 64);
struct ProbeHotData {
  std::shared_ptr<const void> memory;  // owns both arrays
  const ProbeHotCell* cells = nullptr;
  const float* probes = nullptr;
  std::size_t stride = 0;    // floats per probe record (a multiple of 16)
  std::size_t sh_count = 0;  // SH floats per probe (3 bands^2); the position follows them
  const float* probe(std::size_t k) const { return probes + k * stride; }
};
}  // namespace detail

struct ProbeWalkSettings {
  int max_steps = 64;      // steps of the walk from the start cell before the fallback locate
  float far_cells = 4.0f;  // a start cell farther than this many grid cells: fallback at once
};

struct ProbeWalkResult {
  std::int32_t cell = kNoCell;  // the cell holding p; -1 for a cloud without cells
  std::array<std::int32_t, 4> probes{-1, -1, -1, -1};  // probe of each weight (-1: none)
  std::array<float, 4> weights{};                      // convex: >= 0, sum 1 (all 0 for 0 probes)
  int steps = 0;          // cells stepped across, the fallback's included
  bool fallback = false;  // the fallback locate ran (or no cells)
};

// Uniform grid over the inner tetrahedra's bounding boxes: per grid cell, an inner tetrahedron
// near its centre (of those whose box overlaps it, the one whose centroid is nearest; empty grid
// cells take a neighbour's). About two tetrahedra per grid cell, at most 2^21 grid cells.
class ProbeCellGrid {
 public:
  ProbeCellGrid() = default;
  explicit ProbeCellGrid(const data::ProbeCloud& cloud);

  bool empty() const { return start_.empty(); }
  // An inner tetrahedron near p (p clamped into the grid's box); -1 when the cloud has none.
  std::int32_t start_cell(const glm::vec3& p) const;
  float cell_size() const { return cell_size_; }  // the largest edge of a grid cell, metres
  std::array<int, 3> resolution() const { return {nx_, ny_, nz_}; }

 private:
  glm::vec3 origin_{0.0f}, inv_size_{0.0f};
  float cell_size_ = 0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::int32_t> start_;
};

class ProbeTetWalk {
 public:
  // Throws std::invalid_argument naming the field when the cloud's sizes or indices are
  // inconsistent (sh, transforms, inner_count, a probe or neighbour index out of range).
  explicit ProbeTetWalk(std::shared_ptr<const data::ProbeCloud> cloud,
                        const ProbeWalkSettings& settings = {});

  const data::ProbeCloud& cloud() const { return *cloud_; }
  const std::shared_ptr<const data::ProbeCloud>& cloud_ptr() const { return cloud_; }
  const ProbeWalkSettings& settings() const { return settings_; }
  const ProbeCellGrid& grid() const { return grid_; }
  const detail::ProbeHotData& hot() const { return hot_; }  // the records the walk reads

  // The cell holding p, walking from `start` (-1: none). `path`, when given, receives the
  // cells visited in order (the start and the final cell included).
  ProbeWalkResult locate(const glm::vec3& p, std::int32_t start,
                         std::vector<std::int32_t>* path = nullptr) const;

  // What locate(p, ...) returned when it found `cell` for p, rebuilt without a walk: the cell's
  // weights at p made convex (and snapped to a probe), as every walk ends; steps 0, no fallback
  // flag. For a cloud without cells (cell -1) the nearest probe. The system smooths unmoved
  // entities towards this (their unsmoothed sample is not stored).
  ProbeWalkResult at(std::int32_t cell, const glm::vec3& p) const;

  // The four probes' SH weighted by the result's weights.
  ProbeSh interpolate(const ProbeWalkResult& r) const;
  // The same at the bands of `out` (2..4): zero past the cloud's bands, the cloud's bands past
  // out's dropped. At the cloud's own bands (3 by default: 27 floats, not 48) this reads and
  // writes no more than the cloud holds; ProbeLighting takes 3 bands this way.
  void interpolate(const ProbeWalkResult& r, sh::CoeffsRgb<2>& out) const;
  void interpolate(const ProbeWalkResult& r, sh::CoeffsRgb<3>& out) const;
  void interpolate(const ProbeWalkResult& r, ProbeSh& out) const;
  // A hint to the cache: what locate() from `cell` reads first (the cell's hot record, one
  // line, and its neighbours) or, with `probes`, its probes' records (SH and position; this
  // reads the cell's record: issue the first hint a few points earlier). Batch loops call it some
  // entities ahead, so the cached cells' memory arrives while earlier entities compute (each locate
  // otherwise waits on its cell's first load). No effect on results; any value of `cell` is allowed
  // (out of range: nothing).
  // Always inlined: GCC 12 finds an out-of-line prefetch() free of side effects (it only reads
  // memory and hints the cache), marks it pure and drops every call to it; the hints then
  // never reach the caller's loop (none were in the binary before this).
  [[gnu::always_inline]] void prefetch(std::int32_t cell, bool probes) const {
    if (cell < 0 || static_cast<std::size_t>(cell) >= cell_count_) return;
    const detail::ProbeHotCell& h = hot_.cells[static_cast<std::size_t>(cell)];
    if (!probes) {
      __builtin_prefetch(&h);  // one line
      // The neighbours, which a step reads (about one entity in eight moving 8 cm a frame).
      __builtin_prefetch(&cloud_->cells[static_cast<std::size_t>(cell)].neighbours);
      return;
    }
    const std::size_t bytes = (hot_.sh_count + 3) * sizeof(float);
    for (std::int32_t v : h.vertices) {
      if (v < 0) continue;
      const char* b = reinterpret_cast<const char*>(hot_.probe(static_cast<std::size_t>(v)));
      for (std::size_t o = 0; o < bytes; o += 64) __builtin_prefetch(b + o);  // whole lines
    }
  }

  // locate + interpolate for many points: cells[i] is the start on entry and the found cell on
  // return; out[i] the SH. Spans of equal size (std::invalid_argument otherwise). Returns the
  // number of points that needed the fallback. Pure over disjoint spans: call it from several
  // threads on separate slices.
  std::size_t locate_batch(std::span<const glm::vec3> points, std::span<std::int32_t> cells,
                           std::span<ProbeSh> out) const;
  // The same with the SH at 2 or 3 bands (interpolate(r, out) above).
  std::size_t locate_batch(std::span<const glm::vec3> points, std::span<std::int32_t> cells,
                           std::span<sh::CoeffsRgb<3>> out) const;
  std::size_t locate_batch(std::span<const glm::vec3> points, std::span<std::int32_t> cells,
                           std::span<sh::CoeffsRgb<2>> out) const;

 private:
  ProbeWalkResult walk(const glm::vec3& p, std::int32_t start, int cap, float far2, bool& done,
                       std::vector<std::int32_t>* path) const;
  ProbeWalkResult brute_force(const glm::vec3& p) const;
  ProbeWalkResult no_cells(const glm::vec3& p) const;
  template <int kOutBands>
  std::size_t batch(std::span<const glm::vec3> points, std::span<std::int32_t> cells,
                    std::span<sh::CoeffsRgb<kOutBands>> out) const;

  std::shared_ptr<const data::ProbeCloud> cloud_;
  ProbeWalkSettings settings_;
  ProbeCellGrid grid_;
  detail::ProbeHotData hot_;
  std::size_t cell_count_ = 0;
};

// The SH of `probes` weighted by `weights` (probe -1 or weight 0 skipped), 4 bands zero-padded.
// Throws std::invalid_argument when cloud.bands is not 2..4.
ProbeSh interpolate_probe_sh(const data::ProbeCloud& cloud,
                             const std::array<std::int32_t, 4>& probes,
                             const std::array<float, 4>& weights);
// The same at out's bands (2..4; ProbeTetWalk::interpolate(r, out)).
void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, sh::CoeffsRgb<2>& out);
void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, sh::CoeffsRgb<3>& out);
void interpolate_probe_sh(const data::ProbeCloud& cloud, const std::array<std::int32_t, 4>& probes,
                          const std::array<float, 4>& weights, ProbeSh& out);

}  // namespace penumbra::probe_cloud
