// Terrain group, same-run machine baselines: the vector peak and the streaming-read bandwidth on
// both threads, the units of every floor (terrain_bench_common.h).
//
//   baseline/peak_ops               AVX2 FMA chains (kPeakChains independent ones, 8 lanes)
//   baseline/stream_read_mib/8      parallel sum of an 8 MiB buffer: fits the L3
//   baseline/stream_read_mib/256    parallel sum of a 256 MiB buffer: DRAM
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include "peak_iterations.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

float peak_chunk(float seed) {
#ifdef __AVX2__
  __m256 a[kPeakChains];
  for (int j = 0; j < kPeakChains; ++j) a[j] = _mm256_set1_ps(seed + j);
  const __m256 m = _mm256_set1_ps(0.999f), c = _mm256_set1_ps(1e-3f);
  for (int r = 0; r < kPeakReps; ++r)
    for (int j = 0; j < kPeakChains; ++j) a[j] = _mm256_fmadd_ps(a[j], m, c);
  __m256 s = a[0];
  for (int j = 1; j < kPeakChains; ++j) s = _mm256_add_ps(s, a[j]);
  float out[8];
  _mm256_storeu_ps(out, s);
  return out[0] + out[7];
#else
  float a[kPeakChains * 8];
  for (int j = 0; j < kPeakChains * 8; ++j) a[j] = seed + j;
  for (int r = 0; r < kPeakReps; ++r)
    for (float& x : a) x = std::fma(x, 0.999f, 1e-3f);
  return a[0] + a[kPeakChains * 8 - 1];
#endif
}

// The baselines report, besides the median time, their best iteration as a counter ("best_ns"):
// a peak is what the machine can do, so the fastest iteration (the one least disturbed by other
// processes) estimates it best, and a floor built on it stays a lower bound.
template <class F>
double best_of_iterations(benchmark::State& state, F&& body) {
  double best = 1e300;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  state.counters["best_ns"] = best;
  return best;
}

// The peak's best iteration among those every thread ran (peak_iterations.h); thread indices
// above 63 share a bit, so at most 64 threads are told apart.
void BM_PeakOps(benchmark::State& state) {
  std::vector<float> sink(kPeakChunks);
  const int threads = std::min(tbb::this_task_arena::max_concurrency(), 64);
  PeakIterations peak(threads);
  for (auto _ : state) {
    std::atomic<std::uint64_t> seen{0};
    const auto t0 = std::chrono::steady_clock::now();
    tbb::parallel_for(
        0, kPeakChunks,
        [&](int i) {
          seen.fetch_or(std::uint64_t{1} << (tbb::this_task_arena::current_thread_index() & 63),
                        std::memory_order_relaxed);
          sink[i] = peak_chunk(static_cast<float>(i));
        },
        tbb::simple_partitioner());
    benchmark::DoNotOptimize(sink.data());
    peak.add(
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count(),
        std::popcount(seen.load(std::memory_order_relaxed)));
  }
  state.counters["best_ns"] = peak.best_ns();
  state.counters["peak_threads"] = threads;  // the summary compares the two
  state.counters["peak_threads_seen"] = peak.threads_seen();
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPeakOpsPerIteration));
}

float sum_floats(const float* p, std::size_t n) {
  std::size_t i = 0;
  float s = 0;
#ifdef __AVX2__
  __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
  for (; i + 32 <= n; i += 32) {
    a0 = _mm256_add_ps(a0, _mm256_loadu_ps(p + i));
    a1 = _mm256_add_ps(a1, _mm256_loadu_ps(p + i + 8));
    a2 = _mm256_add_ps(a2, _mm256_loadu_ps(p + i + 16));
    a3 = _mm256_add_ps(a3, _mm256_loadu_ps(p + i + 24));
  }
  float t[8];
  _mm256_storeu_ps(t, _mm256_add_ps(_mm256_add_ps(a0, a1), _mm256_add_ps(a2, a3)));
  for (float x : t) s += x;
#endif
  for (; i < n; ++i) s += p[i];
  return s;
}

// Arg: buffer size in MiB.
void BM_StreamRead(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0)) * 1024 * 1024 / sizeof(float);
  std::vector<float> buf(n, 1.0f);
  best_of_iterations(state, [&] { benchmark::DoNotOptimize(stream_read(buf.data(), n)); });
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(n * sizeof(float)));
}

}  // namespace

float stream_read(const float* p, std::size_t n) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 1 << 15), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& r, float acc) {
        return acc + sum_floats(p + r.begin(), r.size());
      },
      [](float a, float b) { return a + b; });
}

void register_machine_baselines() {
  pb::add("baseline/peak_ops", runs(20, 5), BM_PeakOps);
  pb::add("baseline/stream_read_mib", runs(20, 5), BM_StreamRead)->Arg(8);
  pb::add("baseline/stream_read_mib", runs(3, 5), BM_StreamRead)->Arg(256);
}

}  // namespace penumbra::terrain_bench
