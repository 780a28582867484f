// Terrain group, the machine's moment: the horizon sweep on one thread per vCPU, both at once.
//
//   probe/vcpu_sweep/start   before the goal cases
//   probe/vcpu_sweep/end     after the last of them (1024^2)
//
// This machine's two vCPUs are not always equally fast: for spells of seconds to minutes one of
// them runs the sweep's walk (latency- and branch-bound) 1.3-1.6x slower while the FMA chains
// that set the floor unit slow less or not at all (docs/terrain_shadow.md, "Twelfth round").
// A run's ratios then read high without any change in the code. The probe pins one thread to
// each of the first two CPUs the process may run on, sweeps the bench's field (256^2, 32
// azimuths) on each kPasses times, both at once, and reports each vCPU's median: the summary
// shows them against the one-thread floor, so a reader can tell a slow moment from a slower
// build. Nothing else reads them (no goal, no floor of another case).
#include <pthread.h>
#include <sched.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

constexpr int kPasses = 9;

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

// kPasses sweeps on the calling thread (a one-thread arena: TBB's workers stay out), pinned to
// `cpu`; their median in ms, or a negative value when the thread could not be pinned.
double median_sweep_ms(int cpu, std::atomic<int>& ready, int threads) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  const bool pinned = pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
  const auto field = scene_field(kSize);
  ts::HorizonParams p;
  p.azimuths = 32;
  p.height_scale = tbr::kHeightScale;
  p.clamp_at_zero = true;
  ts::HorizonGrid grid;
  ts::SweepWorkspace workspace;
  std::vector<double> ms;
  tbb::task_arena one(1);
  one.execute([&] {
    ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid, workspace);  // warm
    ready.fetch_add(1);
    while (ready.load() < threads) std::this_thread::yield();  // start together
    for (int i = 0; i < kPasses; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid, workspace);
      const auto t1 = std::chrono::steady_clock::now();
      ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
  });
  std::nth_element(ms.begin(), ms.begin() + kPasses / 2, ms.end());
  return pinned ? ms[kPasses / 2] : -ms[kPasses / 2];
}

void BM_VcpuSweep(benchmark::State& state) {
  const std::vector<int> cpus = allowed_cpus(2);
  std::vector<double> ms(cpus.size(), 0.0);
  for (auto _ : state) {
    std::atomic<int> ready{0};
    std::vector<std::thread> threads;
    const int n = static_cast<int>(cpus.size());
    for (int i = 0; i < n; ++i)
      threads.emplace_back([&, i] { ms[i] = median_sweep_ms(cpus[i], ready, n); });
    for (std::thread& t : threads) t.join();
  }
  // Counters: cpuK (the CPU's number) and msK (its median; negative: not pinned), K = 0, 1.
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    state.counters["cpu" + std::to_string(i)] = cpus[i];
    state.counters["ms" + std::to_string(i)] = ms[i];
  }
  const double pairs = static_cast<double>(kSize) * kSize * 32;
  state.counters["ops"] = pairs * kSweepOpsPerPair;
}

}  // namespace

void register_vcpu_probe(const char* when) {
  pb::add(std::string("probe/vcpu_sweep/") + when, runs(1, 1), BM_VcpuSweep);
}

}  // namespace penumbra::terrain_bench
