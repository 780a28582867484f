// Terrain group, the machine's moment: the horizon sweep on one thread per vCPU, both at once,
// before each goal case and after the last:
//
//   probe/vcpu_sweep/0 .. 6   before the environment update, the horizons, the transfer, the
//                             lights, the edit and 1024^2, then after it (terrain_bench_main.cpp)
//
// This machine's two vCPUs are not always equally fast: for spells of seconds to minutes one of
// them runs the sweep's walk (latency- and branch-bound) 1.3-1.8x slower while the FMA chains
// that set the floor unit slow less or not at all (docs/terrain_shadow_log.md, "Twelfth round").
// A run's ratios then read high without any change in the code. The probe pins one thread to
// each of the first two CPUs the process may run on, sweeps the bench's field (256^2, 32
// azimuths) on each kPasses times, both at once, and reports each vCPU's median: the summary
// shows them against the one-thread floor, so a reader can tell a slow moment from a slower
// build. Beside it, a measure our code does not set: the latency of a pointer chase through an
// L2-sized buffer, which reads 10-40% higher on a vCPU in its slow moments (another thread on
// the same core, docs/terrain_shadow_log.md, "Thirteenth round"). Nothing else reads them (no goal,
// no floor of another case).
#include <pthread.h>
#include <sched.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

constexpr int kPasses = 5;

// The first `n` CPUs in this process's affinity set (fewer if it has fewer).
std::vector<int> allowed_cpus(int n) {
  std::vector<int> cpus;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE && static_cast<int>(cpus.size()) < n; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

// Nanoseconds per load of a pointer chase through `bytes` (one load per 64-byte line, in a random
// cycle; the best of three rounds): a latency that the sweep does not set but that moves with it.
double chase_ns(std::size_t bytes) {
  const std::size_t lines = bytes / 64, stride = 64 / sizeof(std::size_t);
  std::vector<std::size_t> order(lines), next(lines * stride);
  for (std::size_t i = 0; i < lines; ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(42));
  for (std::size_t i = 0; i < lines; ++i) next[order[i] * stride] = order[(i + 1) % lines] * stride;
  std::size_t at = 0;
  for (std::size_t i = 0; i < lines; ++i) at = next[at];  // into the cache
  double best = 1e300;
  constexpr int kLoads = 1 << 18;
  for (int round = 0; round < 3; ++round) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kLoads; ++i) at = next[at];
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / kLoads);
  }
  benchmark::DoNotOptimize(at);
  return best;
}

struct VcpuReading {
  double sweep_ms = 0;  // median; negative: the thread could not be pinned
  double l2_ns = 0;     // chase_ns over 512 KiB (fits this machine's 1 MiB L2)
};

// kPasses sweeps on the calling thread (a one-thread arena: TBB's workers stay out), pinned to
// `cpu`, and the L2 latency there just before them.
VcpuReading read_vcpu(const data::HeightField& field, int cpu, std::atomic<int>& ready,
                      int threads) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  const bool pinned = pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
  const ts::HorizonParams p = env_horizon_params(32);
  ts::HorizonGrid grid;
  ts::SweepWorkspace workspace;
  std::vector<double> ms;
  VcpuReading out;
  tbb::task_arena one(1);
  one.execute([&] {
    ts::sweep_horizons(field, p, ts::TexelRect::all(field), grid, workspace);  // warm
    ready.fetch_add(1);
    while (ready.load() < threads) std::this_thread::yield();  // start together
    out.l2_ns = chase_ns(512 * 1024);
    for (int i = 0; i < kPasses; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      ts::sweep_horizons(field, p, ts::TexelRect::all(field), grid, workspace);
      const auto t1 = std::chrono::steady_clock::now();
      ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
  });
  std::nth_element(ms.begin(), ms.begin() + kPasses / 2, ms.end());
  out.sweep_ms = pinned ? ms[kPasses / 2] : -ms[kPasses / 2];
  return out;
}

void BM_VcpuSweep(benchmark::State& state) {
  const std::vector<int> cpus = allowed_cpus(2);
  const auto field = scene_field(kSize);  // here: scene_field is not thread-safe
  std::vector<VcpuReading> readings(cpus.size());
  for (auto _ : state) {
    std::atomic<int> ready{0};
    std::vector<std::thread> threads;
    const int n = static_cast<int>(cpus.size());
    for (int i = 0; i < n; ++i)
      threads.emplace_back([&, i] { readings[i] = read_vcpu(*field, cpus[i], ready, n); });
    for (std::thread& t : threads) t.join();
  }
  // Counters, K = 0, 1: cpuK (the CPU's number), msK (its sweeps' median; negative: not
  // pinned), l2nsK (its L2 latency); ops and peak_threads for the one-thread floor.
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    const std::string k = std::to_string(i);
    state.counters["cpu" + k] = cpus[i];
    state.counters["ms" + k] = readings[i].sweep_ms;
    state.counters["l2ns" + k] = readings[i].l2_ns;
  }
  const double pairs = static_cast<double>(kSize) * kSize * 32;
  state.counters["ops"] = pairs * kSweepOpsPerPair;
  // The threads the vector peak runs on (TBB's default arena): one thread's share of it.
  state.counters["peak_threads"] = tbb::this_task_arena::max_concurrency();
}

}  // namespace

std::vector<std::string>& vcpu_probe_labels() {
  static std::vector<std::string> labels;
  return labels;
}

void register_vcpu_probe(const std::string& label) {
  pb::add("probe/vcpu_sweep/" + std::to_string(vcpu_probe_labels().size()), runs(1, 1),
          BM_VcpuSweep);
  vcpu_probe_labels().push_back(label);
}

}  // namespace penumbra::terrain_bench
