// Benchmark group "blockers", speed versus accuracy (blocker_bench.cpp has the kernels and
// main, blocker_frame_bench.cpp the frames): one frame per configuration on a window of the
// frames' receivers, with its irradiance difference against all pairs at the same bands.
//
//  - receivers  the central 158 x 158 of the frames' 316 x 316 grid (24,964 upward receivers
//               over 100 m x 100 m, the frames' spacing, so clusters keep their size);
//  - scenes     scattered:400 and objects:400 (the frames' scenes, blocker_frame_bench.cpp);
//  - bands      3, 4, 5;
//  - methods    all_pairs (min_sin 0, hierarchy off: the reference of the error, and the
//               speed baseline); the per-receiver method (grid for the scattered spheres,
//               hierarchy for the objects) at min_sin 0.02, 0.05, 0.1, 0.2; clusters
//               (ReceiverClusters, kObjects) at the same min_sin with far_error 0.005 (the
//               default), and at min_sin 0.05 with far_error 0.002 and 0.02.
//
// Each point: median of 3 frames (2 threads, wall clock, set_blockers included, as the frames);
// counters computed outside the timed loop: view_blocker calls and log-SH additions per
// receiver (every receiver), mean HYB squarings (every 50th), and the irradiance's relative
// RMS and max difference against all pairs at every receiver: sqrt(sum (E - E_all)^2 /
// sum E_all^2), max |E - E_all| / RMS(E_all); also the RMS one against all pairs at 5 bands,
// which adds the band limit's share (the same-bands error is the price of the cut-offs only).
// blocker_records.cpp turns them into records and
// the speed-versus-accuracy chart.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bench_json.h"
#include "bench_registry.h"
#include "blocker_bench.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/blocker_accumulation/receiver_clusters.h"

namespace {
namespace pb = penumbra::bench;
namespace bb = penumbra::bench::blockers;
namespace ba = penumbra::blocker_accumulation;
namespace sh = penumbra::sh;

using bb::kBlock;
using bb::kThreads;
constexpr std::size_t kSquaresStride = 50;
constexpr int kGridSide = 316;  // the frames' grid (blocker_bench.cpp)
constexpr int kWindowSide = 158;

struct Receivers {
  std::vector<glm::vec3> points, normals;
};

const Receivers& window() {
  static const Receivers w = [] {
    const std::vector<glm::vec3> all = bb::receiver_grid();
    Receivers x;
    const int first = (kGridSide - kWindowSide) / 2;
    for (int j = first; j < first + kWindowSide; ++j)
      for (int i = first; i < first + kWindowSide; ++i)
        x.points.push_back(all[static_cast<std::size_t>(j) * kGridSide + i]);
    x.normals.assign(x.points.size(), glm::vec3(0, 0, 1));
    return x;
  }();
  return w;
}

template <int N>
const sh::CoeffsRgb<N>& uniform_sky() {
  static const sh::CoeffsRgb<N> sky = [] {
    sh::CoeffsRgb<N> x{};
    for (auto& c : x) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
    return x;
  }();
  return sky;
}

ba::BlockerSettings settings_of(const bb::SweepPoint& p) {
  ba::BlockerSettings s;
  s.blocker.min_sin = p.method == "all_pairs" ? 0.0f : p.min_sin;
  s.hierarchy = p.method == "hierarchy" || p.method == "clusters" ? ba::BlockerHierarchy::kObjects
                                                                  : ba::BlockerHierarchy::kOff;
  return s;
}

// One frame of `p` into `out` (set_blockers included).
template <int N>
void frame(const bb::SweepPoint& p, ba::BlockerAccumulation<N>& acc,
           const ba::ReceiverClusters<N>* clusters, tbb::task_arena& arena,
           std::vector<glm::vec3>& out) {
  const Receivers& w = window();
  const bb::FrameScene& scene = bb::frame_scene(p.scene);
  acc.set_blockers(scene.spheres, scene.groups);
  const std::span<glm::vec3> irradiance(out);
  if (clusters) {
    arena.execute([&] { clusters->shade(acc, uniform_sky<N>(), irradiance); });
    return;
  }
  const std::span<const glm::vec3> points(w.points), normals(w.normals);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kBlock),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        acc.shade(uniform_sky<N>(), points.subspan(r.begin(), r.size()),
                                  normals.subspan(r.begin(), r.size()), {},
                                  irradiance.subspan(r.begin(), r.size()));
                      });
  });
}

// All pairs' irradiance per scene at N bands: the reference of the error (filled by the
// all_pairs point when it runs first, else computed here once).
template <int N>
const std::vector<glm::vec3>& all_pairs_output(const std::string& scene,
                                               const std::vector<glm::vec3>* measured = nullptr) {
  static std::map<std::string, std::vector<glm::vec3>> cache;
  auto it = cache.find(scene);
  if (it != cache.end()) return it->second;
  if (measured) return cache.emplace(scene, *measured).first->second;
  bb::SweepPoint p;
  p.scene = scene;
  p.method = "all_pairs";
  ba::BlockerAccumulation<N> acc(settings_of(p));
  tbb::task_arena arena(kThreads);
  std::vector<glm::vec3> out(window().points.size());
  frame<N>(p, acc, nullptr, arena, out);
  return cache.emplace(scene, std::move(out)).first->second;
}

struct SweepAnalysis {
  double views = 0, added = 0, depth_evals = 0;  // per receiver
  double squares = 0;
  double rel_rms = 0, max_rel = 0;
  double rel_rms_5 = 0;  // against all pairs at 5 bands (the band limit's share included)
};

// sqrt(sum (E - E_ref)^2 / sum E_ref^2) and max |E - E_ref| / RMS(E_ref) over every receiver.
std::pair<double, double> difference(const std::vector<glm::vec3>& out,
                                     const std::vector<glm::vec3>& ref) {
  double diff2 = 0, ref2 = 0, max_diff = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double e = out[i].y, r = ref[i].y;
    diff2 += (e - r) * (e - r);
    ref2 += r * r;
    max_diff = std::max(max_diff, std::abs(e - r));
  }
  if (!(ref2 > 0)) return {0.0, 0.0};
  return {std::sqrt(diff2 / ref2), max_diff / std::sqrt(ref2 / static_cast<double>(out.size()))};
}

template <int N>
SweepAnalysis analyse_sweep(const bb::SweepPoint& p, const ba::BlockerAccumulation<N>& acc,
                            const ba::ReceiverClusters<N>* clusters,
                            const std::vector<glm::vec3>& out) {
  const Receivers& w = window();
  const double receivers = static_cast<double>(w.points.size());
  SweepAnalysis a;
  if (clusters) {
    ba::ReceiverClusterCounts cc;
    std::vector<glm::vec3> scratch(w.points.size());
    clusters->shade(acc, uniform_sky<N>(), scratch, {}, &cc);
    a.views = static_cast<double>(cc.receiver_views + cc.centre_views) / receivers;
    a.added = static_cast<double>(cc.receiver_adds + cc.centre_adds) / receivers;
    a.depth_evals = static_cast<double>(cc.depth_evaluations) / receivers;
  } else {
    typename ba::BlockerAccumulation<N>::PairCounts counts;
    for (std::size_t i = 0; i < w.points.size(); ++i)
      acc.log_visibility(w.points[i], w.normals[i], &counts);
    a.views = static_cast<double>(counts.views) / receivers;
    a.added = static_cast<double>(counts.adds) / receivers;
    a.depth_evals = static_cast<double>(counts.depth_evaluations) / receivers;
  }
  double k_sum = 0;
  int samples = 0;
  for (std::size_t i = 0; i < w.points.size(); i += kSquaresStride, ++samples) {
    const sh::Coeffs<N> lv = acc.log_visibility(w.points[i], w.normals[i]);
    double norm2 = 0;
    for (int c = 1; c < N * N; ++c) norm2 += double(lv[c]) * lv[c];
    if (std::sqrt(norm2) > sh::kHybOlNorm)
      k_sum += std::ceil(std::log2(std::sqrt(norm2) / sh::kHybOlNorm));
  }
  a.squares = k_sum / samples;
  std::tie(a.rel_rms, a.max_rel) = difference(out, all_pairs_output<N>(p.scene));
  a.rel_rms_5 = difference(out, all_pairs_output<5>(p.scene)).first;
  return a;
}

template <int N>
void BM_Sweep(benchmark::State& state, bb::SweepPoint p) {
  const Receivers& w = window();
  const bb::FrameScene& scene = bb::frame_scene(p.scene);
  ba::BlockerAccumulation<N> acc(settings_of(p));
  std::optional<ba::ReceiverClusters<N>> clusters;
  if (p.method == "clusters") {
    ba::ReceiverClusterSettings cs;
    cs.far_error = p.far_error;
    clusters.emplace(cs);
    clusters->set_receivers(w.points, w.normals);
  }
  tbb::task_arena arena(kThreads);
  std::vector<glm::vec3> out(w.points.size());
  for (auto _ : state) {
    frame<N>(p, acc, clusters ? &*clusters : nullptr, arena, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  if (p.method == "all_pairs") all_pairs_output<N>(p.scene, &out);
  static std::map<std::string, SweepAnalysis> cache;
  auto it = cache.find(p.key);
  if (it == cache.end())
    it = cache.emplace(p.key, analyse_sweep<N>(p, acc, clusters ? &*clusters : nullptr, out)).first;
  const SweepAnalysis& a = it->second;
  const double receivers = static_cast<double>(w.points.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(w.points.size()));
  state.counters["receivers"] = receivers;
  state.counters["blockers"] = static_cast<double>(scene.spheres.size());
  state.counters["views_per_receiver"] = a.views;
  state.counters["added_per_receiver"] = a.added;
  state.counters["squares_mean"] = a.squares;
  state.counters["flops_per_frame"] =
      receivers * (a.views * bb::view_flops() + a.added * bb::add_log_flops(N) +
                   a.depth_evals * bb::depth_eval_flops(N) + bb::shade_flops(N, a.squares));
  state.counters["rel_rms_vs_all_pairs"] = a.rel_rms;
  state.counters["max_rel_vs_all_pairs"] = a.max_rel;
  state.counters["rel_rms_vs_all_pairs_5_bands"] = a.rel_rms_5;
}

}  // namespace

namespace penumbra::bench::blockers {

const std::vector<SweepPoint>& sweep_points() {
  static const std::vector<SweepPoint> points = [] {
    std::vector<SweepPoint> out;
    const auto add = [&](const std::string& scene, const std::string& method, int bands,
                         float min_sin, float far_error) {
      SweepPoint p;
      p.scene = scene;
      p.method = method;
      p.bands = bands;
      p.min_sin = method == "all_pairs" ? 0.0f : min_sin;
      p.far_error = method == "clusters" ? far_error : 0.0f;
      p.receivers = kWindowSide * kWindowSide;
      p.key = "BM_Sweep/" + scene + "/" + method + "/bands:" + std::to_string(bands);
      if (method != "all_pairs") p.key += "/min_sin:" + bench_json::compact(min_sin);
      if (method == "clusters") p.key += "/far_error:" + bench_json::compact(far_error);
      out.push_back(p);
    };
    for (const char* scene : {"scattered:400", "objects:400"}) {
      const std::string per_receiver =
          std::string(scene).starts_with("objects") ? "hierarchy" : "grid";
      for (int bands : {3, 4, 5}) {
        add(scene, "all_pairs", bands, 0, 0);
        for (float s : {0.02f, 0.05f, 0.1f, 0.2f}) add(scene, per_receiver, bands, s, 0);
        for (float s : {0.02f, 0.05f, 0.1f, 0.2f}) add(scene, "clusters", bands, s, 0.005f);
        for (float e : {0.002f, 0.02f}) add(scene, "clusters", bands, 0.05f, e);
      }
    }
    return out;
  }();
  return points;
}

void register_sweep_benchmarks() {
  const pb::Timing timing{.unit = benchmark::kMillisecond, .iterations = 1, .repetitions = 3};
  for (const SweepPoint& p : sweep_points()) {
    if (p.bands == 3) pb::add(p.key, timing, BM_Sweep<3>, p);
    if (p.bands == 4) pb::add(p.key, timing, BM_Sweep<4>, p);
    if (p.bands == 5) pb::add(p.key, timing, BM_Sweep<5>, p);
  }
}

}  // namespace penumbra::bench::blockers
