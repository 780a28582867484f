// Benchmark group "blockers", the frame (blocker_bench.cpp has the kernels, the floors' counts
// and main): 99,856 upward receivers (316 x 316 over 200 m x 200 m) shaded by
// BlockerAccumulation<4> (kProduct, uniform sky) on 2 threads, tbb::parallel_for over blocks of
// 1,024 receivers, wall clock; each frame also rebuilds the grid (set_blockers), as the
// system's gather does. Scenes:
//  - scattered:N  N = 50 or 400 spheres, radius 1-3 m, heights 2-10 m, each its own group;
//  - objects:400  25 objects of 16 spheres (radius 0.5-1.5 m within 3 m of the object's
//                 centre, heights 2-10 m), one BlockerGroup each (bound + disc coverage,
//                 computed as the system's gather does).
// Methods: all_pairs (min_sin = 0: the grid lists every sphere everywhere; hierarchy off: the
// same-run baseline), grid (default min_sin, hierarchy off), hierarchy (grid + kObjects),
// clusters (ReceiverClusters, default settings, kObjects; receivers clustered once outside the
// timed loop, shade() parallel over clusters).
// Counters (computed outside the timed loop): view_blocker calls and log-SH additions per
// receiver, counted by the library's own loop (log_visibility's PairCounts) at every
// receiver; the counted operations of a frame (for the floor); and, at every 50th receiver
// (1,998), the mean number of HYB squarings and the irradiance's relative RMS and max
// difference against all_pairs (same settings otherwise): sqrt(sum (E - E_all)^2 / sum E_all^2),
// max |E - E_all| / RMS(E_all).
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "bench_registry.h"
#include "blocker_bench.h"
#include "common/random_draws.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/blocker_accumulation/receiver_clusters.h"

namespace {
namespace pb = penumbra::bench;
namespace bb = penumbra::bench::blockers;
namespace ba = penumbra::blocker_accumulation;
namespace sh = penumbra::sh;

constexpr int N = 4;  // kSystemBands
using bb::kBlock;
using bb::kThreads;
constexpr std::size_t kStride = 50;  // accuracy and squarings subsample
using bb::kGoalMs;

using Scene = bb::FrameScene;  // groups empty: every sphere its own group

Scene objects_scene() {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> xy(-100, 100), z(4, 8), r(0.5f, 1.5f), u(-1, 1);
  Scene scene;
  for (int o = 0; o < 25; ++o) {
    const glm::vec3 centre = penumbra::test::draw_zyx<glm::vec3>(rng, xy, xy, z);
    const auto first = static_cast<std::uint32_t>(scene.spheres.size());
    for (int k = 0; k < 16; ++k) {
      glm::vec3 d;
      do d = penumbra::test::draw_zyx<glm::vec3>(rng, u);
      while (glm::dot(d, d) > 1);
      scene.spheres.push_back({centre + 3.0f * d, r(rng)});
    }
    scene.groups.push_back(ba::bound_group(std::span(scene.spheres).subspan(first, 16), first));
  }
  return scene;
}

enum class Method { kAllPairs, kGrid, kHierarchy, kClusters };

ba::BlockerSettings settings_for(Method m) {
  ba::BlockerSettings s;
  s.hierarchy = m == Method::kHierarchy || m == Method::kClusters ? ba::BlockerHierarchy::kObjects
                                                                  : ba::BlockerHierarchy::kOff;
  if (m == Method::kAllPairs) s.blocker.min_sin = 0;
  return s;
}

struct Fixture {
  std::vector<glm::vec3> points, normals;
  sh::CoeffsRgb<N> sky{};  // uniform radiance 1
  std::map<std::string, Scene> scenes;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    x.points = bb::receiver_grid();
    x.normals.assign(x.points.size(), glm::vec3(0, 0, 1));
    for (auto& c : x.sky) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
    x.scenes["scattered:50"] = {bb::scattered_spheres(50), {}};
    x.scenes["scattered:400"] = {bb::scattered_spheres(400), {}};
    x.scenes["objects:400"] = objects_scene();
    return x;
  }();
  return f;
}

// The receivers clustered once (default ReceiverClusterSettings: at most 256 per cluster).
const ba::ReceiverClusters<N>& clusters() {
  static const ba::ReceiverClusters<N> rc = [] {
    ba::ReceiverClusters<N> x;
    x.set_receivers(fixture().points, fixture().normals);
    return x;
  }();
  return rc;
}

struct FrameAnalysis {
  double views = 0, added = 0;  // per receiver
  double flops = 0;             // per frame
  double squares = 0;           // mean HYB squarings
  double rel_rms = 0, max_rel = 0;
};

// Replays accumulate() (blocker_accumulation.cpp) at every receiver: which view_blocker calls
// and log-SH additions it makes, and the depth limit's evaluations.
FrameAnalysis analyse_frame(const Scene& scene, Method m) {
  const Fixture& f = fixture();
  const ba::BlockerSettings settings = settings_for(m);
  ba::BlockerAccumulation<N> acc(settings), all(settings_for(Method::kAllPairs));
  acc.set_blockers(scene.spheres, scene.groups);
  all.set_blockers(scene.spheres, scene.groups);
  // What the library's own loop costs per receiver (log_visibility's PairCounts); for the
  // clusters, their own counts (views and adds at receivers plus those at cluster centres).
  typename ba::BlockerAccumulation<N>::PairCounts counts;
  std::vector<glm::vec3> clustered;
  if (m == Method::kClusters) {
    ba::ReceiverClusterCounts cc;
    clustered.resize(f.points.size());
    clusters().shade(acc, f.sky, clustered, {}, &cc);
    counts.views = cc.receiver_views + cc.centre_views;
    counts.adds = cc.receiver_adds + cc.centre_adds;
    counts.depth_evaluations = cc.depth_evaluations;
  } else {
    for (std::size_t i = 0; i < f.points.size(); ++i)
      acc.log_visibility(f.points[i], f.normals[i], &counts);
  }
  const double views = static_cast<double>(counts.views), added = static_cast<double>(counts.adds),
               depth_evals = static_cast<double>(counts.depth_evaluations);
  FrameAnalysis a;
  const double receivers = static_cast<double>(f.points.size());
  a.views = views / receivers;
  a.added = added / receivers;
  double k_sum = 0, diff2 = 0, ref2 = 0, max_diff = 0;
  int samples = 0;
  for (std::size_t i = 0; i < f.points.size(); i += kStride, ++samples) {
    const sh::Coeffs<N> lv = acc.log_visibility(f.points[i], f.normals[i]);
    double norm2 = 0;
    for (int c = 1; c < N * N; ++c) norm2 += double(lv[c]) * lv[c];
    if (std::sqrt(norm2) > sh::kHybOlNorm)
      k_sum += std::ceil(std::log2(std::sqrt(norm2) / sh::kHybOlNorm));
    const double e = m == Method::kClusters ? clustered[i].y
                                            : acc.irradiance(f.sky, f.points[i], f.normals[i]).y;
    const double ref = all.irradiance(f.sky, f.points[i], f.normals[i]).y;
    diff2 += (e - ref) * (e - ref);
    ref2 += ref * ref;
    max_diff = std::max(max_diff, std::abs(e - ref));
  }
  a.squares = k_sum / samples;
  a.rel_rms = ref2 > 0 ? std::sqrt(diff2 / ref2) : 0.0;
  a.max_rel = ref2 > 0 ? max_diff / std::sqrt(ref2 / samples) : 0.0;
  a.flops = views * bb::view_flops() + added * bb::add_log_flops(N) +
            depth_evals * bb::depth_eval_flops(N) + receivers * bb::shade_flops(N, a.squares);
  return a;
}

void BM_Frame(benchmark::State& state, std::string scene_name, Method m) {
  const Fixture& f = fixture();
  const Scene& scene = f.scenes.at(scene_name);
  ba::BlockerAccumulation<N> acc(settings_for(m));
  tbb::task_arena arena(kThreads);
  std::vector<glm::vec3> out(f.points.size());
  const std::span<const glm::vec3> points(f.points), normals(f.normals);
  const std::span<glm::vec3> irradiance(out);
  for (auto _ : state) {
    acc.set_blockers(scene.spheres, scene.groups);
    if (m == Method::kClusters) {  // parallel over clusters inside shade()
      arena.execute([&] { clusters().shade(acc, f.sky, irradiance); });
      benchmark::DoNotOptimize(out.data());
      benchmark::ClobberMemory();
      continue;
    }
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kBlock),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          acc.shade(f.sky, points.subspan(r.begin(), r.size()),
                                    normals.subspan(r.begin(), r.size()), {},
                                    irradiance.subspan(r.begin(), r.size()));
                        });
    });
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  static std::map<std::pair<std::string, Method>, FrameAnalysis> cache;
  auto it = cache.find({scene_name, m});
  if (it == cache.end())
    it = cache.emplace(std::pair(scene_name, m), analyse_frame(scene, m)).first;
  const FrameAnalysis& a = it->second;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(f.points.size()));
  state.counters["receivers"] = static_cast<double>(f.points.size());
  state.counters["views_per_receiver"] = a.views;
  state.counters["added_per_receiver"] = a.added;
  state.counters["flops_per_frame"] = a.flops;
  state.counters["squares_mean"] = a.squares;
  state.counters["rel_rms_vs_all_pairs"] = a.rel_rms;
  state.counters["max_rel_vs_all_pairs"] = a.max_rel;
}

const char* method_name(Method m) {
  switch (m) {
    case Method::kAllPairs:
      return "all_pairs";
    case Method::kGrid:
      return "grid";
    case Method::kHierarchy:
      return "hierarchy";
    case Method::kClusters:
      return "clusters";
  }
  return "";
}

std::string key(const std::string& scene, Method m) {
  return "BM_Frame/" + scene + "/" + method_name(m);
}

struct FrameCase {
  const char* scene;
  Method method;
};
constexpr FrameCase kCases[] = {
    {"scattered:50", Method::kAllPairs},  {"scattered:50", Method::kGrid},
    {"scattered:400", Method::kAllPairs}, {"scattered:400", Method::kGrid},
    {"objects:400", Method::kAllPairs},   {"objects:400", Method::kGrid},
    {"objects:400", Method::kHierarchy},  {"scattered:50", Method::kClusters},
    {"scattered:400", Method::kClusters}, {"objects:400", Method::kClusters},
};

using pb::fmt;

}  // namespace

namespace penumbra::bench::blockers {

const FrameScene& frame_scene(const std::string& name) {
  return fixture().scenes.at(name);
}

std::vector<FrameCaseInfo> frame_cases() {
  std::vector<FrameCaseInfo> out;
  for (const FrameCase& c : kCases)
    out.push_back({key(c.scene, c.method), c.scene, method_name(c.method)});
  return out;
}

void register_frame_benchmarks() {
  const pb::Timing frame{.unit = benchmark::kMillisecond, .iterations = 2, .repetitions = 5};
  for (const FrameCase& c : kCases)
    pb::add(key(c.scene, c.method), frame, BM_Frame, std::string(c.scene), c.method);
}

void summarize_frames(const Results& r, Summary& s, double ns_per_fma) {
  const auto ms = [&](const std::string& k) { return pb::scale(r.real_ns(k), 1e-6); };
  const auto floor_ms = [&](const std::string& k) -> std::optional<double> {
    const auto flops = r.counter(k, "flops_per_frame");
    if (!flops || !(ns_per_fma > 0)) return std::nullopt;
    return *flops * ns_per_fma / kThreads * 1e-6;
  };
  const auto pairs_note = [&](const std::string& k) {
    return fmt("%.1f", r.counter(k, "views_per_receiver").value_or(NAN)) + " views, " +
           fmt("%.1f", r.counter(k, "added_per_receiver").value_or(NAN)) +
           " log-SH adds per receiver";
  };
  const auto accuracy_note = [&](const std::string& k) {
    return "; irradiance vs all pairs: rel RMS " +
           fmt("%.3g%%", 100 * r.counter(k, "rel_rms_vs_all_pairs").value_or(NAN)) + ", max " +
           fmt("%.3g%%", 100 * r.counter(k, "max_rel_vs_all_pairs").value_or(NAN));
  };
  for (const FrameCase& c : kCases) {
    const std::string k = key(c.scene, c.method);
    const std::string name = std::string("frame ") + c.scene + " " + method_name(c.method);
    if (c.method == Method::kAllPairs) {
      add_row(s, name, "ms", ms(k), std::nullopt, pb::Goal::none(), floor_ms(k),
              "same-run baseline (min_sin 0); " + pairs_note(k));
    } else if (c.method == Method::kGrid) {
      add_row(s, name, "ms", ms(k), ms(key(c.scene, Method::kAllPairs)), pb::Goal::none(),
              floor_ms(k), "baseline: all pairs; " + pairs_note(k) + accuracy_note(k));
    } else if (c.method == Method::kClusters) {
      const bool objects = std::string(c.scene).starts_with("objects");
      const Method base = objects ? Method::kHierarchy : Method::kGrid;
      const auto vs_all = pb::quotient(ms(key(c.scene, Method::kAllPairs)), ms(k));
      add_row(s, name, "ms", ms(k), ms(key(c.scene, base)), pb::Goal::none(), floor_ms(k),
              std::string("baseline: ") + method_name(base) + " (per receiver); " +
                  fmt("%.1fx", vs_all.value_or(NAN)) +
                  " all pairs; receivers clustered once (at most 256 each); " + pairs_note(k) +
                  " (cluster centres' share included)" + accuracy_note(k));
    } else {
      const auto vs_all = pb::quotient(ms(key(c.scene, Method::kAllPairs)), ms(k));
      add_row(s, name, "ms", ms(k), ms(key(c.scene, Method::kGrid)), pb::Goal::none(), floor_ms(k),
              "baseline: grid, hierarchy off (kOff); " + fmt("%.1fx", vs_all.value_or(NAN)) +
                  " all pairs; " + pairs_note(k) + accuracy_note(k));
    }
  }
  for (const FrameCase& g :
       {FrameCase{"scattered:400", Method::kGrid}, FrameCase{"objects:400", Method::kHierarchy},
        FrameCase{"scattered:400", Method::kClusters},
        FrameCase{"objects:400", Method::kClusters}}) {
    const std::string k = key(g.scene, g.method);
    const auto value = ms(k);
    const auto over = pb::quotient(value, kGoalMs);
    add_row(s, std::string("goal: 100k receivers x ") + g.scene + " " + method_name(g.method), "ms",
            value, std::nullopt, pb::Goal::value_at_most(kGoalMs), floor_ms(k),
            "issue 11: <= 30 ms on 2 cores, exponentials included; measured / goal = " +
                fmt("%.2fx", over.value_or(NAN)));
  }
}

}  // namespace penumbra::bench::blockers
