// Registration and main() of the Penumbra benchmark groups (ecs, sh, reference, render,
// terrain), written once:
//
//   void register_benchmarks() {
//     pb::add("group/case", {.unit = benchmark::kMillisecond, .iterations = 10, .repetitions = 9},
//             BM_Case, extra_args...)->Arg(8);
//   }
//   int main(int argc, char** argv) {
//     return pb::run_group(argc, argv, "group", register_benchmarks, summarize);
//   }
//
// A Timing says how one benchmark is timed: which clock (wall by default: the executors and the
// TBB loops run work on other threads; the CPU clock for single-threaded kernels; manual when
// the benchmark times its own intervals), the display unit, a fixed iteration count or a minimum
// time (neither: Google Benchmark's default), and repetitions (more than 1: only their
// aggregates are displayed, and the summary takes the median, bench_report.h).
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "bench_report.h"

namespace penumbra::bench {

// The floors' unit: scalar FMA throughput, 8 independent chains so latency is hidden; 8,192
// FMAs per iteration (ns per FMA = real or CPU time / 8192). The sh, blockers and probes groups
// register it as "BM_FmaThroughput".
inline void BM_FmaThroughput(benchmark::State& state) {
  float a[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  const float m = 0.999f, c = 1e-3f;
  for (auto _ : state) {
    for (int i = 0; i < 1024; ++i)
      for (float& x : a) x = std::fma(x, m, c);
    benchmark::DoNotOptimize(a);
  }
  state.SetItemsProcessed(state.iterations() * 8192);
}

// The floor unit from BM_FmaThroughput's CPU time (ns per FMA; 0 when it did not run), added to
// the summary as its first row with `note`.
inline double add_fma_floor_row(const Results& r, Summary& s, const std::string& note) {
  const auto m = r.get("BM_FmaThroughput");
  const std::optional<double> fma = m ? std::optional<double>(m->cpu_ns / 8192) : std::nullopt;
  Row row;
  row.name = "scalar FMA throughput (floor unit)";
  row.unit = "ns/FMA";
  row.value = fma;
  row.note = note;
  s.add(row);
  return fma.value_or(0.0);
}

struct Timing {
  enum class Clock { kWall, kCpu, kManual };
  Clock clock = Clock::kWall;
  benchmark::TimeUnit unit = benchmark::kNanosecond;
  double min_time = 0;                       // seconds per benchmark; 0: the default
  benchmark::IterationCount iterations = 0;  // a fixed count (then no min_time); 0: not fixed
  int repetitions = 1;
};

// Applies `timing` to a registered benchmark; returns it for ->Arg(...) and the like.
inline benchmark::internal::Benchmark* apply(benchmark::internal::Benchmark* b,
                                             const Timing& timing) {
  b->Unit(timing.unit);
  if (timing.clock == Timing::Clock::kWall) b->UseRealTime();
  if (timing.clock == Timing::Clock::kManual) b->UseManualTime();
  if (timing.iterations > 0) b->Iterations(timing.iterations);
  if (timing.min_time > 0) b->MinTime(timing.min_time);
  if (timing.repetitions > 1) b->Repetitions(timing.repetitions)->DisplayAggregatesOnly(true);
  return b;
}

// Registers `fn(state, args...)` under `name` (copied), timed as `timing`. Benchmarks run in the
// order they are registered.
template <class Fn, class... Args>
benchmark::internal::Benchmark* add(const std::string& name, const Timing& timing, Fn&& fn,
                                    Args&&... args) {
  return apply(
      benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn), std::forward<Args>(args)...),
      timing);
}

// A group's main(): registers its benchmarks, runs them and prints (with --summary_out, also
// writes) the summary built by `summarize` (run_main), then calls `release` (e.g. to destroy
// the group's executors and devices before static destruction). Returns main()'s status.
inline int run_group(int argc, char** argv, std::string_view group,
                     const std::function<void()>& register_benchmarks,
                     const std::function<Summary(const Results&)>& summarize,
                     const std::function<void()>& release = {}) {
  register_benchmarks();
  const int status = run_main(argc, argv, group, summarize);
  if (release) release();
  return status;
}

}  // namespace penumbra::bench
