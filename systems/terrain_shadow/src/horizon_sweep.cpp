// Line-sweep horizons (Timonen and Westerholm 2010) and the brute-force ray march.
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "fast_math.h"
#include "sweep_geometry.h"
#include "sweep_lanes.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;

float to_angle(float slope, bool any, bool clamp) {
  if (!any) return clamp ? 0.0f : -kHalfPi;
  const float a = detail::fast_atan(slope);
  return clamp ? std::max(a, 0.0f) : a;
}

struct HullPoint {
  int j;
  float h;
};

// Per-task buffers, reused across azimuths and lines.
struct Scratch {
  std::vector<float> acc, weight;  // region-sized, (minor, major) layout
  std::vector<HullPoint> hull;
  // One line's receivers in the region: major coordinate, lower texel, offset, slope (-inf:
  // nothing ahead) then angle.
  std::vector<int> u, bi;
  std::vector<float> t, value;
};

// One azimuth over the region: sweep every line that passes through it, scatter the line
// samples' horizons onto the texels between lines (weights by minor distance) and write them
// to `plane` (region-sized, row-major in x, y).
void sweep_direction(const data::HeightField& f, const HorizonParams& p, const TexelRect& r,
                     double phi, Scratch& sc, float* plane) {
  const detail::AzimuthFrame frame(f, phi);
  // Region in (major, minor) coordinates, half-open.
  const int u0 = frame.x_major ? r.x0 : r.y0, u1 = frame.x_major ? r.x1 : r.y1;
  const int v0 = frame.x_major ? r.y0 : r.x0, v1 = frame.x_major ? r.y1 : r.x1;
  const int rw = u1 - u0;
  sc.acc.assign(r.count(), 0.0f);
  sc.weight.assign(r.count(), 0.0f);

  // Lines b = c + slope * u with integer c bracketing every texel of the region.
  const double lo = std::min(v0 - frame.slope * u0, v0 - frame.slope * (u1 - 1));
  const double hi = std::max((v1 - 1) - frame.slope * u0, (v1 - 1) - frame.slope * (u1 - 1));
  const int c_lo = static_cast<int>(std::floor(lo)) - 1, c_hi = static_cast<int>(std::ceil(hi)) + 1;
  // Far end first: the horizon looks along +step, so sweep from the far side of the field down
  // to the near edge of the region.
  const int u_far = frame.step > 0 ? frame.major_size - 1 : 0;
  const int u_near = frame.step > 0 ? u0 : u1 - 1;
  const double bmax = frame.minor_size - 1;
  const float mps = frame.metres_per_step;

  for (int c = c_lo; c <= c_hi; ++c) {
    // Columns where the line is inside the field (b = c + slope * u in [0, bmax]), clipped to
    // the swept span, widened by one and re-checked exactly by height_at below.
    int ua = 0, ub = frame.major_size - 1;
    if (frame.slope != 0) {
      const double e0 = -c / frame.slope, e1 = (bmax - c) / frame.slope;
      ua = std::max(ua, static_cast<int>(std::floor(std::min(e0, e1))) - 1);
      ub = std::min(ub, static_cast<int>(std::ceil(std::max(e0, e1))) + 1);
    } else if (c < 0 || c > bmax) {
      continue;
    }
    if (frame.step > 0)
      ub = std::min(ub, u_far), ua = std::max(ua, u_near);
    else
      ua = std::max(ua, u_far), ub = std::min(ub, u_near);
    if (ua > ub) continue;

    // Pass 1, sequential: the hull (Timonen 2010, sec. 4) gives each sample's steepest slope.
    // Fixed-size arrays indexed directly: this loop runs for every sample of every azimuth.
    const std::size_t cap = static_cast<std::size_t>(frame.major_size);
    if (sc.hull.size() < cap) {
      sc.hull.resize(cap), sc.u.resize(cap), sc.bi.resize(cap), sc.t.resize(cap);
      sc.value.resize(cap);
    }
    HullPoint* hull = sc.hull.data();
    std::size_t top = 0, n = 0;  // hull size, receivers recorded
    const int u_start = frame.step > 0 ? ub : ua, u_end = frame.step > 0 ? ua : ub;
    for (int u = u_start;; u -= frame.step) {
      double b;
      float h;
      if (frame.height_at(f, p.height_scale, c, u, b, h)) {
        const int j = frame.step * u;
        // Pop the top while the second is at least as steep (compared without dividing).
        while (top >= 2 && (hull[top - 2].h - h) * static_cast<float>(hull[top - 1].j - j) >=
                               (hull[top - 1].h - h) * static_cast<float>(hull[top - 2].j - j))
          --top;
        if (u >= u0 && u < u1) {
          const int bi = static_cast<int>(b);
          sc.u[n] = u;
          sc.bi[n] = bi;
          sc.t[n] = static_cast<float>(b - bi);
          sc.value[n] = top > 0 ? detail::slope_between(j, h, hull[top - 1].j, hull[top - 1].h, mps)
                                : -std::numeric_limits<float>::infinity();  // atan: -pi/2
          ++n;
        }
        hull[top++] = {j, h};
      }
      if (u == u_end) break;
    }
    // Pass 2, vectorisable: slopes to angles.
    detail::fast_atan_array(sc.value.data(), n);
    if (p.clamp_at_zero)
      for (std::size_t i = 0; i < n; ++i) sc.value[i] = std::max(sc.value[i], 0.0f);
    // Pass 3: the line lies t above texel bi and 1 - t below texel bi + 1.
    for (std::size_t i = 0; i < n; ++i) {
      const int bi = sc.bi[i], u = sc.u[i];
      const float t = sc.t[i], angle = sc.value[i];
      if (bi >= v0 && bi < v1 && t < 1.0f) {
        const std::size_t q = static_cast<std::size_t>(bi - v0) * rw + (u - u0);
        sc.acc[q] += (1.0f - t) * angle;
        sc.weight[q] += 1.0f - t;
      }
      if (bi + 1 >= v0 && bi + 1 < v1 && t > 0.0f) {
        const std::size_t q = static_cast<std::size_t>(bi + 1 - v0) * rw + (u - u0);
        sc.acc[q] += t * angle;
        sc.weight[q] += t;
      }
    }
  }

  const int w = r.width();
  for (int v = v0; v < v1; ++v)
    for (int u = u0; u < u1; ++u) {
      const std::size_t i = static_cast<std::size_t>(v - v0) * rw + (u - u0);
      const int x = frame.x_major ? u : v, y = frame.x_major ? v : u;
      plane[static_cast<std::size_t>(y - r.y0) * w + (x - r.x0)] =
          sc.weight[i] > 0 ? sc.acc[i] / sc.weight[i] : 0.0f;
    }
}

void sweep_azimuth(const data::HeightField& f, const HorizonParams& p, const TexelRect& r, int k,
                   Scratch& sc, float* plane) {
  sweep_direction(f, p, r, detail::azimuth_angle(k, p.azimuths), sc, plane);
}

void prepare_output(const data::HeightField& f, const HorizonParams& p, HorizonGrid& out) {
  if (out.width != f.width || out.height != f.height || out.azimuths != p.azimuths)
    out.resize(f.width, f.height, p.azimuths);
}

}  // namespace

// Per thread, one task's kernel scratch; shared by the threads, one region-sized plane per
// azimuth (as many floats as the region's records) and the field's padded copies.
struct SweepWorkspace::Buffers {
  struct Task {
    Scratch scalar;
#ifdef __AVX2__
    detail::LaneScratch lanes;
#endif
  };
  tbb::enumerable_thread_specific<Task> tasks;
  std::vector<float, CacheLineAllocator<float>> planes;
  std::vector<int> plane_writer;  // per plane slot, the arena thread that wrote it last (-1: none)
#ifdef __AVX2__
  detail::LaneFields fields;
  // Per azimuth, the line groups' hulls that edits left (sweep_lanes.h, GroupHull): valid for
  // `fields` as it is and these params; any other sweep with this workspace clears them.
  std::vector<std::vector<detail::GroupHull>> edit_hulls;
  std::vector<detail::EditBand> edit_bands;  // per azimuth; cleared with the hulls
  int hulls_azimuths = 0;
  float hulls_scale = 0;
#endif
};

SweepWorkspace::SweepWorkspace() : buffers_(std::make_unique<Buffers>()) {}
SweepWorkspace::~SweepWorkspace() = default;
SweepWorkspace::SweepWorkspace(SweepWorkspace&&) noexcept = default;
SweepWorkspace& SweepWorkspace::operator=(SweepWorkspace&&) noexcept = default;
SweepWorkspace::SweepWorkspace(const SweepWorkspace& other)
    : buffers_(std::make_unique<Buffers>()), sole_writer_(other.sole_writer_) {}
SweepWorkspace& SweepWorkspace::operator=(const SweepWorkspace& other) {
  sole_writer_ = other.sole_writer_;
#ifdef __AVX2__
  if (buffers_) buffers_->edit_bands.clear();  // the grid they mirror is being reassigned
#endif
  return *this;
}
SweepWorkspace::Buffers& SweepWorkspace::buffers() {
  if (!buffers_) buffers_ = std::make_unique<Buffers>();
  return *buffers_;
}

namespace {

// kLanes: sixteen lines per step on AVX2 lanes (sweep_lanes.h); kScalar: one line at a time.
enum class Kernel { kScalar, kLanes };

// Which plane slot holds which azimuth in one sweep. A thread takes a slot that it wrote in the
// last sweep where one is free: a plane the other vCPU wrote, or read for the records, is in
// that vCPU's caches, and writing it costs a trip between the two for every line (with the
// azimuths handed out so that every plane had changed sides, the sweep took 17% longer on two
// threads: docs/terrain_shadow_log.md, "Twenty-sixth round"). Which thread sweeps which azimuth
// stays the scheduler's choice. take() is thread-safe; keep() after the sweep's loop.
class PlaneSlots {
 public:
  // last_writer: per slot, the arena thread that wrote it in the last sweep (-1: none).
  PlaneSlots(std::vector<int>& last_writer, int azimuths)
      : last_(last_writer),
        taken_(std::make_unique<std::atomic<bool>[]>(static_cast<std::size_t>(azimuths))),
        slot_of_(static_cast<std::size_t>(azimuths)),
        writer_(static_cast<std::size_t>(azimuths), -1) {
    if (last_.size() != writer_.size()) last_.assign(writer_.size(), -1);
  }
  // A free slot for azimuth k, swept by arena thread `me`: one `me` wrote last time if any.
  std::size_t take(int k, int me) {
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t s = 0; s < writer_.size(); ++s)
        if ((pass == 1 || last_[s] == me) && !taken_[s].exchange(true, std::memory_order_relaxed)) {
          slot_of_[static_cast<std::size_t>(k)] = s;
          writer_[s] = me;
          return s;
        }
    throw std::logic_error("PlaneSlots: more azimuths than slots");
  }
  std::size_t slot(int k) const { return slot_of_[static_cast<std::size_t>(k)]; }
  int writer(int k) const { return writer_[slot(k)]; }
  void keep() { last_ = writer_; }

 private:
  std::vector<int>& last_;
  std::unique_ptr<std::atomic<bool>[]> taken_;
  std::vector<std::size_t> slot_of_;
  std::vector<int> writer_;
};

// body(task) for every task in [0, n) on the arena's threads: each thread first the tasks whose
// home(task) is its arena index, front to back, then the others from the back (where their own
// threads take them last).
template <class Home, class Body>
void run_home_first(int n, const Home& home, const Body& body) {
  const auto taken = std::make_unique<std::atomic<bool>[]>(static_cast<std::size_t>(n));
  const int workers = std::clamp(tbb::this_task_arena::max_concurrency(), 1, n);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, workers, 1),
      [&](const tbb::blocked_range<int>&) {
        const int me = tbb::this_task_arena::current_thread_index();
        for (int i = 0; i < 2 * n; ++i) {
          const int task = i < n ? i : 2 * n - 1 - i;
          if ((home(task) == me) == (i < n) &&
              !taken[static_cast<std::size_t>(task)].exchange(true, std::memory_order_relaxed))
            body(task);
        }
      },
      tbb::simple_partitioner());
}

void sweep(const data::HeightField& field, const HorizonParams& params, const TexelRect& region,
           HorizonGrid& out, Kernel kernel, SweepWorkspace::Buffers& ws) {
  validate_horizon_input(field, params, region);
  if (params.limit_to_point)
    throw std::invalid_argument(
        field.source + ": the line sweep has no distance limit (use march or brute force)");
  prepare_output(field, params, out);
  if (region.empty()) return;
#ifdef __AVX2__
  if (kernel == Kernel::kLanes) ws.fields.assign(field);
  ws.edit_hulls.clear();  // kept for the fields they were taken on
  ws.edit_bands.clear();  // the records they mirror are rewritten
#else
  kernel = Kernel::kScalar;
#endif
  // Two parallel loops: every azimuth into its own plane (one task an azimuth, taken by
  // whichever thread is free, so that a thread that runs faster than the other for a while, as a
  // virtual machine's can, sweeps more of them: docs/terrain_shadow_log.md, "Eighth round"), then
  // the planes into the texels' records block by block (a contiguous run per texel, not one
  // strided float per azimuth, which would touch every record's cache line once per azimuth).
  // An azimuth's task waits for nothing, so a thread's scratch serves one azimuth at a time.
  // One loop over blocks that each swept and wrote their own azimuths was 3-10% slower at 256^2
  // (its last block's records on one thread while the other waited: "Twentieth round").
  // Blocks of 16 azimuths write whole cache lines of the records, with streaming stores
  // (texel_records); 8 write half lines, each read for ownership twice. 16 from 256^2 texels
  // (measured there and at 1024^2: docs/terrain_shadow_log.md, "Horizons, fourth round"), while
  // there are blocks for every thread; smaller regions (not measured) keep 8 and their records
  // in cache.
  const bool wide = region.count() >= 256 * 256 &&
                    params.azimuths / 16 >= tbb::this_task_arena::max_concurrency();
  constexpr int kWideBlock = 16;
  const int block_size = wide ? kWideBlock : 8;
  const int blocks = (params.azimuths + block_size - 1) / block_size;
  const std::size_t count = region.count();
  ws.planes.resize(static_cast<std::size_t>(params.azimuths) * count);
  float* const planes = ws.planes.data();
  PlaneSlots slots(ws.plane_writer, params.azimuths);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, params.azimuths, 1), [&](const tbb::blocked_range<int>& ks) {
        SweepWorkspace::Buffers::Task& task = ws.tasks.local();  // this thread's scratch
        for (int k = ks.begin(); k < ks.end(); ++k) {
          float* plane =
              planes + slots.take(k, tbb::this_task_arena::current_thread_index()) * count;
#ifdef __AVX2__
          if (kernel == Kernel::kLanes) {
            detail::sweep_azimuth_lanes(field, ws.fields, params, region, k, task.lanes, plane);
            continue;
          }
#endif
          sweep_azimuth(field, params, region, k, task.scalar, plane);
        }
      });
  slots.keep();
  // The records in bands of rows as well, at least eight tasks: with one task a block, a vCPU
  // running slower than the other for a while (a slow moment, docs/terrain_shadow.md) held up the
  // sweep's end with its block's records (docs/terrain_shadow_log.md, "Twenty-fifth round"). A
  // block's bands go first to the thread that wrote most of its planes: they are in its caches,
  // and the next sweep's writes find them there.
  const int bands = std::clamp((8 + blocks - 1) / blocks, 1, region.height());
  std::vector<int> home(static_cast<std::size_t>(blocks));
  for (int b = 0; b < blocks; ++b) {
    std::vector<int> wrote(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()), 0);
    for (int k = b * block_size; k < std::min((b + 1) * block_size, params.azimuths); ++k)
      if (const int t = slots.writer(k); t >= 0 && t < std::ssize(wrote))
        ++wrote[static_cast<std::size_t>(t)];
    home[static_cast<std::size_t>(b)] =
        static_cast<int>(std::max_element(wrote.begin(), wrote.end()) - wrote.begin());
  }
  run_home_first(
      blocks * bands, [&](int task) { return home[static_cast<std::size_t>(task / bands)]; },
      [&](int task) {
        const int block = task / bands, band = task % bands;
        const int k0 = block * block_size, k1 = std::min(k0 + block_size, params.azimuths);
        const int y0 = region.y0 + region.height() * band / bands;
        const int y1 = region.y0 + region.height() * (band + 1) / bands;
        const TexelRect rows{region.x0, y0, region.x1, y1};
        // This band's first texel in each azimuth's plane (region-sized, row-major).
        const float* band_planes[kWideBlock];
        for (int k = k0; k < k1; ++k)
          band_planes[k - k0] = planes + slots.slot(k) * count +
                                static_cast<std::size_t>(y0 - region.y0) * region.width();
#ifdef __AVX2__
        detail::texel_records(band_planes, rows, k0, k1, out);
#else
        std::size_t i = 0;
        for (int y = rows.y0; y < rows.y1; ++y)
          for (int x = rows.x0; x < rows.x1; ++x, ++i) {
            float* dst = out.texel(x, y) + k0;
            for (int k = k0; k < k1; ++k) dst[k - k0] = band_planes[k - k0][i];
          }
#endif
      });
}

}  // namespace

void sweep_horizons(const data::HeightField& field, const HorizonParams& params,
                    const TexelRect& region, HorizonGrid& out) {
  SweepWorkspace workspace;
  sweep(field, params, region, out, Kernel::kLanes, workspace.buffers());
}

void sweep_horizons(const data::HeightField& field, const HorizonParams& params,
                    const TexelRect& region, HorizonGrid& out, SweepWorkspace& workspace) {
  sweep(field, params, region, out, Kernel::kLanes, workspace.buffers());
}

void sweep_direction_horizons(const data::HeightField& field, const HorizonParams& params,
                              double phi, const TexelRect& region, std::vector<float>& out) {
  validate_horizon_input(field, params, region);
  if (params.limit_to_point || !std::isfinite(phi))
    throw std::invalid_argument(field.source +
                                ": sweep_direction_horizons needs a finite azimuth and no limit");
  out.assign(region.count(), 0.0f);
  if (region.empty()) return;
#ifdef __AVX2__
  const detail::LaneFields fields(field);  // the lane kernel, as sweep_horizons
  detail::LaneScratch lanes;
  detail::sweep_direction_lanes(field, fields, params, region, phi, lanes, out.data());
#else
  Scratch sc;
  sweep_direction(field, params, region, phi, sc, out.data());  // [Timonen10] sec. 4
#endif
}

std::size_t sweep_horizons_through(const data::HeightField& field, const HorizonParams& params,
                                   const TexelRect& edited, HorizonGrid& out,
                                   std::vector<unsigned char>& changed) {
  SweepWorkspace workspace;
  return sweep_horizons_through(field, params, edited, out, changed, workspace);
}

std::size_t sweep_horizons_through(const data::HeightField& field, const HorizonParams& params,
                                   const TexelRect& edited, HorizonGrid& out,
                                   std::vector<unsigned char>& changed, SweepWorkspace& workspace) {
  validate_horizon_input(field, params, edited);
  if (params.limit_to_point)
    throw std::invalid_argument(
        field.source + ": the line sweep has no distance limit (use march or brute force)");
  if (out.width != field.width || out.height != field.height || out.azimuths != params.azimuths)
    throw std::invalid_argument(field.source +
                                ": sweep_horizons_through needs the previous horizons");
  changed.resize(static_cast<std::size_t>(field.width) * field.height, 0);
  if (edited.empty()) return 0;
  SweepWorkspace::Buffers& ws = workspace.buffers();
#ifdef __AVX2__
  // The kept hulls hold for the samples ahead of their columns: usable only where the field
  // differs from the one they were taken on (the workspace's copy) inside the edit alone, which
  // the edit's own walks then pass. Anything else (another field, other params) clears them.
  const TexelRect diff = ws.fields.update(field);
  if ((!diff.empty() && (diff.x0 < edited.x0 || diff.y0 < edited.y0 || diff.x1 > edited.x1 ||
                         diff.y1 > edited.y1)) ||
      ws.hulls_azimuths != params.azimuths || ws.hulls_scale != params.height_scale)
    ws.edit_hulls.clear(), ws.edit_bands.clear();
  ws.edit_hulls.resize(static_cast<std::size_t>(params.azimuths));
  ws.edit_bands.resize(static_cast<std::size_t>(params.azimuths));
  ws.hulls_azimuths = params.azimuths;
  ws.hulls_scale = params.height_scale;
  std::atomic<std::size_t> pairs{0};
  // Each thread's scratch (its accumulators are field-sized), as sweep()'s tasks; each azimuth
  // its own hulls.
  tbb::parallel_for(0, params.azimuths, [&](int k) {
    pairs += detail::sweep_azimuth_lines_through(
        field, ws.fields, params, edited, k, ws.tasks.local().lanes, out, changed.data(),
        &ws.edit_hulls[static_cast<std::size_t>(k)],
        workspace.sole_writer() ? &ws.edit_bands[static_cast<std::size_t>(k)] : nullptr);
  });
  return pairs;
#else
  HorizonGrid fresh;
  sweep(field, params, TexelRect::all(field), fresh, Kernel::kScalar, ws);
  for (int y = 0; y < field.height; ++y)
    for (int x = 0; x < field.width; ++x)
      for (int k = 0; k < params.azimuths; ++k)
        if (out.texel(x, y)[k] != fresh.texel(x, y)[k]) {
          out.texel(x, y)[k] = fresh.texel(x, y)[k];
          changed[static_cast<std::size_t>(y) * field.width + x] = 1;
        }
  return fresh.angles.size();
#endif
}

void sweep_horizons_scalar(const data::HeightField& field, const HorizonParams& params,
                           const TexelRect& region, HorizonGrid& out) {
  SweepWorkspace workspace;
  sweep(field, params, region, out, Kernel::kScalar, workspace.buffers());
}

namespace {

// Largest elevation slope seen from (u_start, offset + slope * u_start) at `start_height` along
// the frame's direction, over grid-line samples within max_distance; false if there are none.
bool line_slope(const data::HeightField& field, float scale, const detail::AzimuthFrame& frame,
                double offset, double u_start, float start_height, float max_distance,
                float& best) {
  int u = frame.step > 0 ? static_cast<int>(std::floor(u_start)) + 1
                         : static_cast<int>(std::ceil(u_start)) - 1;
  bool any = false;
  for (; u >= 0 && u < frame.major_size; u += frame.step) {
    const float steps = static_cast<float>((u - u_start) * frame.step);
    if (steps * frame.metres_per_step > max_distance) break;
    double b;
    float h;
    if (!frame.height_at(field, scale, offset, u, b, h)) continue;
    const float s = (h - start_height) / (steps * frame.metres_per_step);
    if (!any || s > best) best = s;
    any = true;
  }
  return any;
}

}  // namespace

namespace {
// ray_horizon along a frame's direction (both overloads).
float frame_horizon(const data::HeightField& field, float height_scale, glm::vec2 start,
                    float start_height, const detail::AzimuthFrame& frame, float max_distance,
                    bool clamp_at_zero) {
  const double us = frame.x_major ? start.x : start.y, bs = frame.x_major ? start.y : start.x;
  float best = 0;
  const bool any = line_slope(field, height_scale, frame, bs - frame.slope * us, us, start_height,
                              max_distance, best);
  return to_angle(best, any, clamp_at_zero);
}
}  // namespace

float ray_horizon(const data::HeightField& field, float height_scale, glm::vec2 start,
                  float start_height, float phi, float max_distance, bool clamp_at_zero) {
  return frame_horizon(field, height_scale, start, start_height, detail::AzimuthFrame(field, phi),
                       max_distance, clamp_at_zero);
}

float ray_horizon(const data::HeightField& field, float height_scale, glm::vec2 start,
                  float start_height, glm::vec2 direction, float max_distance, bool clamp_at_zero) {
  return frame_horizon(field, height_scale, start, start_height,
                       detail::AzimuthFrame(field, direction.x, direction.y), max_distance,
                       clamp_at_zero);
}

float sweep_line_horizon(const data::HeightField& field, const HorizonParams& params, int x, int y,
                         int k) {
  float limit = std::numeric_limits<float>::infinity();
  if (params.limit_to_point) {
    const glm::vec2 d = *params.limit_to_point - glm::vec2(x, y) * field.cell_size;
    limit = std::sqrt(d.x * d.x + d.y * d.y);
  }
  // The sweep's two lines either side of the texel, in the sweep's order and weights.
  const detail::AzimuthFrame frame(field, detail::azimuth_angle(k, params.azimuths));
  const int u = frame.x_major ? x : y, v = frame.x_major ? y : x;
  const int c_upper = static_cast<int>(std::ceil(v - frame.slope * u));
  float acc = 0, weight = 0;
  for (int c = c_upper - 1; c <= c_upper; ++c) {
    double b;
    float h;
    if (!frame.height_at(field, params.height_scale, c, u, b, h)) continue;
    const int bi = static_cast<int>(b);
    const float t = static_cast<float>(b - bi);
    const float w = bi == v ? 1.0f - t : (bi + 1 == v ? t : 0.0f);
    if (w <= 0) continue;
    float s = 0;
    const bool any = line_slope(field, params.height_scale, frame, c, u, h, limit, s);
    acc += w * to_angle(s, any, params.clamp_at_zero);
    weight += w;
  }
  return weight > 0 ? acc / weight : 0.0f;
}

void brute_force_horizons(const data::HeightField& field, const HorizonParams& params,
                          const TexelRect& region, HorizonGrid& out, BruteForceSampling sampling) {
  validate_horizon_input(field, params, region);
  prepare_output(field, params, out);
  tbb::parallel_for(region.y0, region.y1, [&](int y) {
    for (int x = region.x0; x < region.x1; ++x) {
      float limit = std::numeric_limits<float>::infinity();
      if (params.limit_to_point) {
        const glm::vec2 d = *params.limit_to_point - glm::vec2(x, y) * field.cell_size;
        limit = std::sqrt(d.x * d.x + d.y * d.y);
      }
      for (int k = 0; k < params.azimuths; ++k) {
        const float phi = detail::azimuth_angle(k, params.azimuths);
        if (sampling == BruteForceSampling::kTexelRays) {
          out.texel(x, y)[k] =
              ray_horizon(field, params.height_scale, glm::vec2(x, y),
                          params.height_scale * field.at(x, y), phi, limit, params.clamp_at_zero);
          continue;
        }
        out.texel(x, y)[k] = sweep_line_horizon(field, params, x, y, k);
      }
    }
  });
}

}  // namespace penumbra::terrain_shadow
