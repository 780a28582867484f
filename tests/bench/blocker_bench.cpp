// Benchmark group "blockers": cost of the blocker accumulation (systems/blocker_accumulation,
// [Giraud] sec. 4.2, [Ren06]) on this machine.
//
//   build/release/tests/bench/bench_blockers [--benchmark_* flags] [--summary_out=PATH]
//       [--records_out=PATH.json] [--chart_out=PATH.svg]
//
// This file: the single-threaded kernels (CPU clock), at 3, 4 and 5 bands:
//  - pair      view_blocker + add_log_visibility over 4,096 receiver-sphere pairs of varied
//              geometry (tilted normals, spheres cut by the tangent plane, receivers inside
//              spheres; none culled), summed as one receiver would; also the two halves alone;
//  - exp       sh::exp_visibility over 1,030 receivers' log-visibility sums taken from the
//              400-blocker frame scene (so the number of HYB squarings is the frame's);
//  - shade     BlockerAccumulation::irradiance() with no blockers and those sums as extra_log:
//              exponential + clamped cosine rotated to the normal + SH product + 3 dots;
//  - fma       scalar FMA throughput (8 independent chains), the unit of the floors.
// blocker_frame_bench.cpp: the frame (100,000 receivers, 50 and 400 blockers, 2 threads; all
// pairs, grid, grid + hierarchy), its pair counts, floors, goal and accuracy against all pairs.
// blocker_sweep_bench.cpp: speed versus accuracy (min_sin, bands, far_error on a window of the
// frame's receivers). blocker_records.cpp: --records_out writes one JSON record per frame case
// and sweep point, --chart_out the speed-versus-accuracy chart (SVG), both atomically.
//
// Floors: floating-point operations counted in the code (below), each FMA, min/max, division,
// square root or transcendental as one, times the measured scalar FMA time: a lower bound on
// one core's issue slots, not a prediction.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "bench_registry.h"
#include "blocker_bench.h"
#include "common/random_draws.h"
#include "penumbra/sh/batch.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/blocker_accumulation/blocker_log_sum.h"

namespace penumbra::bench::blockers {

namespace ba = penumbra::blocker_accumulation;

constexpr int kSide = 316;         // 316 x 316 = 99,856 receivers
constexpr float kExtent = 200.0f;  // metres, centred on the origin
constexpr int kExpStride = 97;     // every 97th receiver of the frame: 1,030 exponential inputs

// The frame's receivers: upward points on z = 0, a kSide x kSide grid over kExtent x kExtent.
std::vector<glm::vec3> receiver_grid() {
  std::vector<glm::vec3> p;
  p.reserve(kSide * kSide);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i)
      p.emplace_back(kExtent * ((i + 0.5f) / kSide - 0.5f), kExtent * ((j + 0.5f) / kSide - 0.5f),
                     0.0f);
  return p;
}

// Spheres of radius 1-3 m over the area at heights 2-10 m.
std::vector<ba::WorldSphere> scattered_spheres(int count) {
  std::mt19937 rng(static_cast<std::uint32_t>(1000 + count));
  std::uniform_real_distribution<float> xy(-0.5f * kExtent, 0.5f * kExtent), z(2, 10), r(1, 3);
  std::vector<ba::WorldSphere> s(count);
  for (auto& x : s) {
    x.centre = {xy(rng), xy(rng), z(rng)};
    x.radius = r(rng);
  }
  return s;
}

// Summary::add_vs_baseline, without "ratio = baseline/value" in the notes of rows that have no
// baseline.
Row& add_row(Summary& s, std::string name, std::string unit, std::optional<double> value,
             std::optional<double> baseline, Goal goal, std::optional<double> floor,
             std::string note) {
  Row& row = s.add_vs_baseline(std::move(name), std::move(unit), value, baseline, goal, floor,
                               std::move(note));
  if (!baseline) row.ratio_def.clear();
  return row;
}

// --- Counted operations -------------------------------------------------------------------

// eval_basis<N>: the generated polynomials (engine/sh/generated/basis_generated.h), counted by
// hand: (x + iy)^m recurrences 2 each, Legendre terms 1-3 each, one multiply per output (three
// for a product of two factors and a constant, the constant product shared by +-m).
double basis_flops(int bands) {
  switch (bands) {
    case 3:
      return 16;
    case 4:
      return 35;
    case 5:
      return 60;
    default:
      return 0;
  }
}

// view_blocker (sphere_blocker.cpp): t = n.(c - p) + r: 7; r' = min(r, t/2): 2;
// c' = c + (r - r') n: 4; c' - p: 3; |.|: 4 (3 + sqrt); axis = to / d: 4; sin = min(r'/d, 1): 2;
// smoothstep(t / 2r) weight: 7; the min_sin fade: 8.
double view_flops() {
  return 41;
}

// add_log_visibility<N>: x = sqrt(max(0, 1 - s^2)): 3; Legendre recurrence: 3 per band after
// the first; eval_basis; scale: 1; per band (P_{l-1} - P_{l+1}) * scale / (2l+1): 3; N^2 FMAs.
double add_log_flops(int n) {
  return 3 + 3 * (n - 1) + basis_flops(n) + 1 + 3 * n + n * n;
}

double product_terms(int bands) {
  switch (bands) {
    case 3:
      return sh::factored_term_count<3>();
    case 4:
      return sh::factored_term_count<4>();
    case 5:
      return sh::factored_term_count<5>();
    default:
      return 0;
  }
}

// exp_visibility<N> (exp_log.cpp), C = N^2 and k squarings: HYB norm C - 1 + sqrt + k: 4;
// scale down: C; OL: norm C - 1 + sqrt, table lerp 10, e^DC 2, outputs 2 + C; k squares of
// factored_term_count terms each; e^DC and scale: 2 + C; the clamp: C - 1 + 5.
double exp_flops(int n, double squares) {
  const double c = n * n;
  return 6 * c + 23 + squares * product_terms(n);
}

// irradiance() after the sum (kProduct): exponential, rotate_zh of the clamped cosine
// (basis + N + C), SH product (factored terms), 3 dots (3C).
double shade_flops(int n, double squares) {
  const double c = n * n;
  return exp_flops(n, squares) + basis_flops(n) + n + c + product_terms(n) + 3 * c;
}

// The depth limit: the sum evaluated at one contributing blocker's axis (basis + C FMAs + max
// and scale).
double depth_eval_flops(int n) {
  return basis_flops(n) + n * n + 2;
}

}  // namespace penumbra::bench::blockers

namespace {
namespace pb = penumbra::bench;
namespace bb = penumbra::bench::blockers;
namespace ba = penumbra::blocker_accumulation;
namespace sh = penumbra::sh;

constexpr int kPairs = 4096;

struct Pair {
  glm::vec3 p, n, centre;
  float radius;
};

// Receivers with normals up to ~60 deg from +z; spheres in the receiver's upper hemisphere at
// 0.5-7.5 radii, above the default min_sin cut-off (some contain the receiver, some are cut by
// its tangent plane).
std::vector<Pair> pairs() {
  std::mt19937 rng(11);
  std::normal_distribution<float> g(0, 1);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Pair> out(kPairs);
  for (Pair& q : out) {
    q.p = {100 * u(rng) - 50, 100 * u(rng) - 50, 5 * u(rng)};
    const float ny = 0.4f * g(rng), nx = 0.4f * g(rng);  // GCC's order (random_draws.h)
    q.n = glm::normalize(glm::vec3(nx, ny, 1.0f));
    glm::vec3 dir = glm::normalize(penumbra::test::draw_zyx<glm::vec3>(rng, g));
    if (glm::dot(dir, q.n) < 0) dir = -dir;
    q.radius = 0.5f + 2.5f * u(rng);
    q.centre = q.p + q.radius * (0.5f + 7.0f * u(rng)) * dir;
  }
  return out;
}

bool none_culled(const std::vector<Pair>& batch, const ba::SphereBlockerSettings& s) {
  for (const Pair& q : batch)
    if (!(ba::view_blocker(q.p, q.n, q.centre, q.radius, s).weight > 0)) return false;
  return true;
}

template <int N>
void BM_Pair(benchmark::State& state) {
  const std::vector<Pair> batch = pairs();
  const ba::SphereBlockerSettings s;
  if (!none_culled(batch, s)) return state.SkipWithError("a pair of the batch is culled");
  const float log_eps = std::log(s.epsilon);
  for (auto _ : state) {
    sh::Coeffs<N> sum{};
    for (const Pair& q : batch)
      ba::add_log_visibility<N>(ba::view_blocker(q.p, q.n, q.centre, q.radius, s), log_eps, sum);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

// The same pairs grouped as 64 receivers of 64 blockers each (receiver r: pair 64 r's point and
// normal; its blockers: the offsets of pairs 64 r .. 64 r + 63, mirrored into its upper
// hemisphere), for the lane path, which shades one receiver's blockers eight at a time.
struct GroupedPairs {
  static constexpr int kPerReceiver = 64;
  std::vector<glm::vec3> p, n;  // per receiver
  std::vector<Pair> blockers;   // kPerReceiver per receiver, in order
};
GroupedPairs grouped_pairs() {
  const std::vector<Pair> all = pairs();
  GroupedPairs g;
  for (std::size_t r = 0; r < all.size() / GroupedPairs::kPerReceiver; ++r) {
    const Pair& at = all[r * GroupedPairs::kPerReceiver];
    g.p.push_back(at.p);
    g.n.push_back(at.n);
    for (int b = 0; b < GroupedPairs::kPerReceiver; ++b) {
      const Pair& q = all[r * GroupedPairs::kPerReceiver + b];
      glm::vec3 off = q.centre - q.p;
      if (glm::dot(off, at.n) < 0) off -= 2 * glm::dot(off, at.n) * at.n;
      g.blockers.push_back({at.p, at.n, at.p + off, q.radius});
    }
  }
  return g;
}

// view_blocker + add_log_visibility per pair on the grouped pairs (the lane path's baseline).
template <int N>
void BM_PairGrouped(benchmark::State& state) {
  const GroupedPairs g = grouped_pairs();
  const ba::SphereBlockerSettings s;
  const float log_eps = std::log(s.epsilon);
  for (auto _ : state)
    for (std::size_t r = 0; r < g.p.size(); ++r) {
      sh::Coeffs<N> sum{};
      for (int b = 0; b < GroupedPairs::kPerReceiver; ++b) {
        const Pair& q = g.blockers[r * GroupedPairs::kPerReceiver + b];
        ba::add_log_visibility<N>(ba::view_blocker(q.p, q.n, q.centre, q.radius, s), log_eps, sum);
      }
      benchmark::DoNotOptimize(sum);
    }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

// The same sums by BlockerLogSum: eight blockers per step on vector lanes.
template <int N>
void BM_PairLanes(benchmark::State& state) {
  const GroupedPairs g = grouped_pairs();
  const ba::SphereBlockerSettings s;
  const float log_eps = std::log(s.epsilon);
  for (auto _ : state)
    for (std::size_t r = 0; r < g.p.size(); ++r) {
      sh::Coeffs<N> sum{};
      ba::BlockerLogSum<N> lanes(g.p[r], g.n[r], s, log_eps);
      for (int b = 0; b < GroupedPairs::kPerReceiver; ++b) {
        const Pair& q = g.blockers[r * GroupedPairs::kPerReceiver + b];
        lanes.add(q.centre, q.radius, 1);
      }
      lanes.finish(sum);
      benchmark::DoNotOptimize(sum);
    }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

void BM_View(benchmark::State& state) {
  const std::vector<Pair> batch = pairs();
  const ba::SphereBlockerSettings s;
  for (auto _ : state) {
    for (const Pair& q : batch) {
      ba::BlockerView v = ba::view_blocker(q.p, q.n, q.centre, q.radius, s);
      benchmark::DoNotOptimize(v);
    }
  }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

template <int N>
void BM_AddLog(benchmark::State& state) {
  const std::vector<Pair> batch = pairs();
  const ba::SphereBlockerSettings s;
  std::vector<ba::BlockerView> views;
  for (const Pair& q : batch) views.push_back(ba::view_blocker(q.p, q.n, q.centre, q.radius, s));
  const float log_eps = std::log(s.epsilon);
  for (auto _ : state) {
    sh::Coeffs<N> sum{};
    for (const ba::BlockerView& v : views) ba::add_log_visibility<N>(v, log_eps, sum);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

// The frame's log-visibility sums (400 scattered blockers, default settings, upward receivers),
// at every kExpStride-th receiver, and the mean number of HYB squarings they take.
template <int N>
std::vector<sh::Coeffs<N>> frame_log_sums(double& squares) {
  ba::BlockerAccumulation<N> acc;
  acc.set_blockers(bb::scattered_spheres(400));
  const std::vector<glm::vec3> points = bb::receiver_grid();
  std::vector<sh::Coeffs<N>> out;
  double k_sum = 0;
  for (std::size_t i = 0; i < points.size(); i += bb::kExpStride) {
    out.push_back(acc.log_visibility(points[i], {0, 0, 1}));
    double norm2 = 0;
    for (int c = 1; c < N * N; ++c) norm2 += double(out.back()[c]) * out.back()[c];
    const double norm = std::sqrt(norm2);
    if (norm > sh::kHybOlNorm) k_sum += std::ceil(std::log2(norm / sh::kHybOlNorm));
  }
  squares = k_sum / static_cast<double>(out.size());
  return out;
}

template <int N>
void BM_Exp(benchmark::State& state) {
  double squares = 0;
  const auto sums = frame_log_sums<N>(squares);
  for (auto _ : state)
    for (const auto& f : sums) benchmark::DoNotOptimize(sh::exp_visibility<N>(f));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(sums.size()));
  state.counters["inputs"] = static_cast<double>(sums.size());
  state.counters["squares_mean"] = squares;
}

template <int N>
void BM_Shade(benchmark::State& state) {
  double squares = 0;
  const auto sums = frame_log_sums<N>(squares);
  const ba::BlockerAccumulation<N> acc;  // no blockers: the sum is all extra_log
  sh::CoeffsRgb<N> sky{};
  for (auto& c : sky) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
  for (auto _ : state)
    for (const auto& f : sums)
      benchmark::DoNotOptimize(acc.irradiance(sky, {0, 0, 0}, {0, 0, 1}, nullptr, &f));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(sums.size()));
  state.counters["squares_mean"] = squares;
}

// The same sums, 8 receivers per call on vector lanes (sh/batch.h): exp_visibility_batch, and
// irradiance_batch (exponential + clamped cosine rotated to the normal + product + 3 dots), array
// of structures in and out (the transposes included), the last batch padded.
template <int N>
void BM_ExpBatch(benchmark::State& state) {
  double squares = 0;
  const auto sums = frame_log_sums<N>(squares);
  std::vector<sh::Coeffs<N>> out(sums.size());
  for (auto _ : state) {
    sh::exp_visibility_batch<N>(std::span<const sh::Coeffs<N>>(sums),
                                std::span<sh::Coeffs<N>>(out));
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(sums.size()));
  state.counters["squares_mean"] = squares;
}

template <int N>
void BM_ShadeBatch(benchmark::State& state) {
  double squares = 0;
  const auto sums = frame_log_sums<N>(squares);
  sh::CoeffsRgb<N> sky{};
  for (auto& c : sky) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
  const std::vector<glm::vec3> normals(sums.size(), glm::vec3(0, 0, 1));
  std::vector<glm::vec3> out(sums.size());
  const sh::Zonal<N> cosine = sh::zh_clamped_cosine<N>();
  for (auto _ : state) {
    sh::irradiance_batch<N>(sky, cosine, sums, normals, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(sums.size()));
  state.counters["squares_mean"] = squares;
}

constexpr pb::Timing kCpu{.clock = pb::Timing::Clock::kCpu, .unit = benchmark::kMicrosecond};

template <int N>
void register_bands() {
  const std::string n = "<" + std::to_string(N) + ">";
  pb::add("BM_Pair" + n, kCpu, BM_Pair<N>);
  pb::add("BM_PairGrouped" + n, kCpu, BM_PairGrouped<N>);
  pb::add("BM_PairLanes" + n, kCpu, BM_PairLanes<N>);
  pb::add("BM_AddLog" + n, kCpu, BM_AddLog<N>);
  pb::add("BM_Exp" + n, kCpu, BM_Exp<N>);
  pb::add("BM_Shade" + n, kCpu, BM_Shade<N>);
  pb::add("BM_ExpBatch" + n, kCpu, BM_ExpBatch<N>);
  pb::add("BM_ShadeBatch" + n, kCpu, BM_ShadeBatch<N>);
}

void register_benchmarks() {
  pb::add("BM_FmaThroughput", kCpu, pb::BM_FmaThroughput);
  pb::add("BM_View", kCpu, BM_View);
  register_bands<3>();
  register_bands<4>();
  register_bands<5>();
  bb::register_frame_benchmarks();
  bb::register_sweep_benchmarks();
}

// Single-threaded kernels: their CPU time (the clock they were timed with).
std::optional<double> cpu_ns(const pb::Results& r, const std::string& key) {
  if (auto m = r.get(key)) return m->cpu_ns;
  return std::nullopt;
}

using pb::fmt;

template <int N>
void summarize_bands(const pb::Results& r, pb::Summary& s, double ns_per_fma) {
  const std::string b = "<" + std::to_string(N) + ">";
  const std::string tag = std::to_string(N) + " bands: ";
  const auto per_pair = [&](const std::string& name) {
    return pb::scale(cpu_ns(r, "BM_" + name + b), 1.0 / kPairs);
  };
  const double pair = bb::view_flops() + bb::add_log_flops(N);
  bb::add_row(s, tag + "pair (view + add_log)", "ns/pair", per_pair("Pair"), std::nullopt,
              pb::Goal::none(), pair * ns_per_fma,
              "4,096 pairs, none culled; floor: " + fmt("%.0f", pair) + " ops (view_blocker " +
                  fmt("%.0f", bb::view_flops()) + ", add_log " + fmt("%.0f", bb::add_log_flops(N)) +
                  ")");
  bb::add_row(s, tag + "pair, 8 lanes (BlockerLogSum)", "ns/pair", per_pair("PairLanes"),
              per_pair("PairGrouped"), pb::Goal::none(), pair * ns_per_fma / sh::kBatch,
              "64 receivers x 64 blockers; baseline: view + add_log per pair on the same pairs; "
              "floor: the scalar one / 8 lanes");
  bb::add_row(s, tag + "add_log_visibility", "ns/pair", per_pair("AddLog"), std::nullopt,
              pb::Goal::none(), bb::add_log_flops(N) * ns_per_fma,
              "views precomputed; basis " + fmt("%.0f", bb::basis_flops(N)) +
                  " ops, Legendre, N^2 multiply-adds");
  const std::string exp_key = "BM_Exp" + b;
  const auto sums = r.counter(exp_key, "inputs");
  const auto per_input = [&](const std::string& key) {
    return sums ? pb::scale(cpu_ns(r, key), 1.0 / *sums) : std::nullopt;
  };
  const double k = r.counter(exp_key, "squares_mean").value_or(0.0);
  const double exp = bb::exp_flops(N, k);
  bb::add_row(s, tag + "exponential (exp_visibility)", "ns", per_input(exp_key), std::nullopt,
              pb::Goal::none(), exp * ns_per_fma,
              "the 400-blocker frame's sums, mean " + fmt("%.2f", k) +
                  " HYB squares; floor: " + fmt("%.0f", exp) + " ops");
  const double shade = bb::shade_flops(N, k) + N * N;
  bb::add_row(s, tag + "shade (irradiance: exp + product + dot)", "ns", per_input("BM_Shade" + b),
              per_input(exp_key), pb::Goal::none(), shade * ns_per_fma,
              "baseline: the exponential alone; floor: " + fmt("%.0f", shade) + " ops");
  bb::add_row(s, tag + "exponential, 8 lanes (exp_visibility_batch)", "ns",
              per_input("BM_ExpBatch" + b), per_input(exp_key), pb::Goal::none(),
              exp * ns_per_fma / sh::kBatch,
              "baseline: exp_visibility (scalar), same sums; floor: the scalar one / 8 lanes");
  bb::add_row(s, tag + "shade, 8 lanes (irradiance_batch)", "ns", per_input("BM_ShadeBatch" + b),
              per_input("BM_Shade" + b), pb::Goal::none(), shade * ns_per_fma / sh::kBatch,
              "baseline: shade (scalar irradiance), same sums; floor: the scalar one / 8 lanes");
}

pb::Summary summarize(const pb::Results& r, const bb::Outputs& out) {
  pb::Summary s;
  const double ns_per_fma =
      pb::add_fma_floor_row(r, s, "8 independent chains; floors = counted operations x this");
  bb::add_row(s, "view_blocker", "ns/pair", pb::scale(cpu_ns(r, "BM_View"), 1.0 / kPairs),
              std::nullopt, pb::Goal::none(), bb::view_flops() * ns_per_fma,
              "plane rule, cap angle, weights");
  summarize_bands<3>(r, s, ns_per_fma);
  summarize_bands<4>(r, s, ns_per_fma);
  summarize_bands<5>(r, s, ns_per_fma);
  bb::summarize_frames(r, s, ns_per_fma);
  bb::write_records(r, ns_per_fma, out);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  bb::Outputs out;
  out.records_path = pb::take_flag(argc, argv, "records_out");
  out.chart_path = pb::take_flag(argc, argv, "chart_out");
  return pb::run_group(argc, argv, "blockers", register_benchmarks,
                       [&](const pb::Results& r) { return summarize(r, out); });
}
