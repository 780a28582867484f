// Benchmark group "ecs": iteration cost of the archetype ECS against plain arrays, job-graph
// scheduling overhead, and parallel speedup of a chunk system.
//
//   build/release/tests/bench/bench_ecs [--benchmark_* flags] [--summary_out=PATH]
//
// After Google Benchmark's normal output, a summary table compares results measured in this
// same run (see bench_report.h):
//
//  1. Iterating 1M entities with Position + Velocity (p += v * dt), single thread, through a
//     prepared Query walking ChunkView spans, through World::query<>().each(), and through a
//     Schedule::add_each system on Executor(1). Baseline: the same loop over a plain
//     std::vector<{Position, Velocity}>. Goal: baseline/ecs >= 0.8. Floor: a streaming loop
//     over flat float arrays moving the same bytes (read 24 B, write 12 B per entity).
//  2. One frame of 100 empty task systems over 20 resource types (each system reads 2 and
//     writes 1, fixed-seed choice), Executor(2) and Executor(1). Goal: <= 100 us per frame on
//     2 threads. Floor: the same reduced graph walked with bare TBB tasks and atomics. An
//     extra row times the frame that follows 2 ms of idle time (workers asleep).
//  3. A compute-bound add_each system (~100 flops per entity) over 1M entities on Executor(1)
//     and Executor(2), wall clock. Goal: speedup t1/t2 >= 1.7. Floor: t1/2.
//
// Every time is wall clock. The 1M-entity motion data (24 MB touched per frame) fits the 32 MB
// L3 of the reference machine, so (1) measures cache bandwidth there, not DRAM. Counter
// "ns_per_entity" holds nanoseconds (the console prints inverted-rate counters with an "s"
// suffix regardless). Multi-threaded rows need an otherwise idle machine.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "bench_registry.h"
#include "penumbra/components/motion.h"
#include "penumbra/ecs/query.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/jobs/schedule.h"

namespace {

namespace ecs = penumbra::ecs;
namespace jobs = penumbra::jobs;
namespace pb = penumbra::bench;
using penumbra::components::Position;
using penumbra::components::Velocity;

constexpr std::size_t kEntities = 1'000'000;
constexpr float kDt = 1.0f / 60.0f;
// Bytes an integration step must move per entity: read Position and Velocity, write Position.
constexpr std::size_t kBytesPerEntity = 2 * sizeof(Position) + sizeof(Velocity);
constexpr double kMinTime = 0.5;  // seconds per benchmark (Google Benchmark's min_time)

// Deterministic generator (SplitMix64): the same data and graph on every platform.
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform(float lo, float hi) {
    const float u = static_cast<float>(next() >> 40) * (1.0f / 16777216.0f);  // [0, 1)
    return lo + (hi - lo) * u;
  }
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }
};

inline void integrate(Position& p, const Velocity& v, float dt) {
  p.x += v.x * dt;
  p.y += v.y * dt;
  p.z += v.z * dt;
}

// ns_per_entity = wall time per iteration / entities (an inverted iteration-invariant rate of
// entities * 1e-9 gives nanoseconds), plus bytes/s of the logical traffic.
void set_entity_counters(benchmark::State& state, std::size_t entities,
                         std::size_t bytes_per_entity) {
  state.counters["ns_per_entity"] = benchmark::Counter(
      static_cast<double>(entities) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(entities));
  state.SetBytesProcessed(state.iterations() *
                          static_cast<std::int64_t>(entities * bytes_per_entity));
}

struct FreeDeleter {
  void operator()(float* p) const { std::free(p); }
};
using FloatArray = std::unique_ptr<float[], FreeDeleter>;
FloatArray make_floats(std::size_t n) {
  const std::size_t bytes = (n * sizeof(float) + 63) & ~std::size_t{63};
  auto* p = static_cast<float*>(std::aligned_alloc(64, bytes));
  if (p == nullptr) throw std::bad_alloc();
  return FloatArray(p);
}

// ---------------------------------------------------------------------------------------------
// 1. Iteration: 1M entities with Position + Velocity.

struct PlainEntity {
  Position p;
  Velocity v;
};

struct MotionFixture {
  ecs::World world;
  ecs::Query<Position, const Velocity> query{world};  // prepared once, reused every frame
  std::vector<PlainEntity> plain;
  FloatArray flat_p, flat_v;  // 3 floats per entity each: the streaming floor
  jobs::Schedule schedule;
  jobs::Executor executor{1};

  MotionFixture() {
    SplitMix rng{42};
    plain.reserve(kEntities);
    flat_p = make_floats(3 * kEntities);
    flat_v = make_floats(3 * kEntities);
    for (std::size_t i = 0; i < kEntities; ++i) {
      const Position p{rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100)};
      const Velocity v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
      world.create_with(p, v);
      plain.push_back({p, v});
      flat_p[3 * i + 0] = p.x, flat_p[3 * i + 1] = p.y, flat_p[3 * i + 2] = p.z;
      flat_v[3 * i + 0] = v.x, flat_v[3 * i + 1] = v.y, flat_v[3 * i + 2] = v.z;
    }
    schedule.add_each<Position, const Velocity>(
        "integrate", [](Position& p, const Velocity& v) { integrate(p, v, kDt); });
    schedule.build();
  }
};

// ---------------------------------------------------------------------------------------------
// 2. Scheduler overhead: 100 empty task systems over 20 types.

constexpr int kSystems = 100;
constexpr std::size_t kTypes = 20;

template <std::size_t N>
struct Tag {
  int unused = 0;
};
using AccessAdder = void (*)(jobs::SystemBuilder&);
template <std::size_t N>
void add_read(jobs::SystemBuilder& b) {
  b.reads<Tag<N>>();
}
template <std::size_t N>
void add_write(jobs::SystemBuilder& b) {
  b.writes<Tag<N>>();
}
template <std::size_t... I>
constexpr std::array<AccessAdder, sizeof...(I)> readers(std::index_sequence<I...>) {
  return {&add_read<I>...};
}
template <std::size_t... I>
constexpr std::array<AccessAdder, sizeof...(I)> writers(std::index_sequence<I...>) {
  return {&add_write<I>...};
}

// Registers the 100 systems: each reads 2 and writes 1 of the 20 types, distinct, fixed seed.
void add_empty_systems(jobs::Schedule& schedule) {
  static constexpr auto kReaders = readers(std::make_index_sequence<kTypes>{});
  static constexpr auto kWriters = writers(std::make_index_sequence<kTypes>{});
  SplitMix rng{2024};
  for (int i = 0; i < kSystems; ++i) {
    const std::uint32_t w = rng.below(kTypes);
    std::uint32_t r1 = rng.below(kTypes);
    while (r1 == w) r1 = rng.below(kTypes);
    std::uint32_t r2 = rng.below(kTypes);
    while (r2 == w || r2 == r1) r2 = rng.below(kTypes);
    jobs::SystemBuilder b =
        schedule.add_task("system " + std::to_string(i), [](jobs::SystemContext&) {});
    kReaders[r1](b);
    kReaders[r2](b);
    kWriters[w](b);
  }
  schedule.build();
}

std::size_t edge_count(const jobs::Schedule& s) {
  std::size_t edges = 0;
  for (const auto& node : s.nodes()) edges += node.successors.size();
  return edges;
}
// Nodes on the longest path (nodes are stored in a topological order).
std::size_t critical_path(const jobs::Schedule& s) {
  const auto& nodes = s.nodes();
  std::vector<std::size_t> depth(nodes.size(), 1);
  std::size_t longest = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    for (std::uint32_t p : nodes[k].predecessors) depth[k] = std::max(depth[k], depth[p] + 1);
    longest = std::max(longest, depth[k]);
  }
  return longest;
}

// The floor for the 2-thread executor: the same reduced graph walked the same way (atomic
// predecessor counts, ready successors spawned into a tbb::task_group, one continued inline)
// with nothing else: no timing, no stats, no std::function, empty bodies.
class RawDag {
 public:
  RawDag(const jobs::Schedule& s, int threads) : arena_(threads) {
    for (const auto& node : s.nodes()) {
      successors_.push_back(node.successors);
      predecessor_count_.push_back(static_cast<std::uint32_t>(node.predecessors.size()));
    }
    pending_ = std::make_unique<std::atomic<std::uint32_t>[]>(successors_.size());
  }
  void run_frame() {
    const std::size_t n = successors_.size();
    for (std::size_t i = 0; i < n; ++i) {
      pending_[i].store(predecessor_count_[i], std::memory_order_relaxed);
    }
    arena_.execute([&] {
      tbb::task_group group;
      for (std::uint32_t k = 0; k < n; ++k) {
        if (predecessor_count_[k] == 0) group.run([this, k, &group] { run_from(k, group); });
      }
      group.wait();
    });
  }

 private:
  void run_from(std::uint32_t k, tbb::task_group& group) {
    for (;;) {
      ran_.fetch_add(1, std::memory_order_relaxed);  // the "system"
      std::uint32_t next = kNone;
      for (std::uint32_t succ : successors_[k]) {
        if (pending_[succ].fetch_sub(1, std::memory_order_acq_rel) != 1) continue;
        if (next == kNone) {
          next = succ;
        } else {
          group.run([this, succ, &group] { run_from(succ, group); });
        }
      }
      if (next == kNone) return;
      k = next;
    }
  }
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  tbb::task_arena arena_;
  std::vector<std::vector<std::uint32_t>> successors_;
  std::vector<std::uint32_t> predecessor_count_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> pending_;
  std::atomic<std::uint64_t> ran_{0};
};

struct ScheduleFixture {
  ecs::World world;
  jobs::Schedule schedule1, schedule2;  // one per executor: nodes hold executor runtime state
  jobs::Executor executor1{1}, executor2{2};
  std::unique_ptr<RawDag> raw2;

  ScheduleFixture() {
    add_empty_systems(schedule1);
    add_empty_systems(schedule2);
    raw2 = std::make_unique<RawDag>(schedule2, 2);
  }
};

// ---------------------------------------------------------------------------------------------
// 3. Parallel speedup: a compute-bound add_each system over 1M entities.

struct Phase {
  float value = 0;
};

// 32 steps of the logistic map (3 flops each) from a seed in (0.05, 0.95): 99 flops per
// entity, values bounded in [0, 1] (no overflow, no denormal drift). Unrolled by a fold so the
// row loop is straight-line code the compiler can vectorise across entities.
constexpr int kLogisticSteps = 32;
constexpr int kFlopsPerEntity = 3 + 3 * kLogisticSteps;
template <std::size_t... K>
inline float logistic_steps(float x, std::index_sequence<K...>) {
  ((x = 3.9f * x * (1.0f - x), static_cast<void>(K)), ...);
  return x;
}
inline float logistic_kernel(const Position& p) {
  const float seed = (p.x + p.y + p.z) * (1.0f / 3.0f);
  return logistic_steps(seed, std::make_index_sequence<kLogisticSteps>{});
}

constexpr int kWarmupFrames = 5;

struct ComputeFixture {
  ecs::World world;
  jobs::Schedule schedule1, schedule2;
  jobs::Executor executor1{1}, executor2{2};

  ComputeFixture() {
    SplitMix rng{7};
    for (std::size_t i = 0; i < kEntities; ++i) {
      world.create_with(
          Position{rng.uniform(0.05f, 0.95f), rng.uniform(0.05f, 0.95f), rng.uniform(0.05f, 0.95f)},
          Phase{});
    }
    for (jobs::Schedule* s : {&schedule1, &schedule2}) {
      s->add_each<const Position, Phase>(
          "logistic", [](const Position& p, Phase& out) { out.value = logistic_kernel(p); });
      s->build();
    }
    // Settle the executors' adaptive grain (it uses the previous frame's ns per chunk).
    for (int f = 0; f < kWarmupFrames; ++f) {
      executor1.run(schedule1, world);
      executor2.run(schedule2, world);
    }
  }
};

// ---------------------------------------------------------------------------------------------
// Fixtures are built on first use and released before main() returns (TBB arenas and 100 MB
// of data should not outlive the benchmark library's shutdown).

std::unique_ptr<MotionFixture> g_motion;
std::unique_ptr<ScheduleFixture> g_schedule;
std::unique_ptr<ComputeFixture> g_compute;

MotionFixture& motion() {
  if (!g_motion) g_motion = std::make_unique<MotionFixture>();
  return *g_motion;
}
ScheduleFixture& sched() {
  if (!g_schedule) g_schedule = std::make_unique<ScheduleFixture>();
  return *g_schedule;
}
ComputeFixture& compute() {
  if (!g_compute) g_compute = std::make_unique<ComputeFixture>();
  return *g_compute;
}

// --- 1. iteration -----------------------------------------------------------------------------

void BM_IteratePlainVector(benchmark::State& state) {
  MotionFixture& f = motion();
  for (auto _ : state) {
    PlainEntity* data = f.plain.data();
    const std::size_t n = f.plain.size();
    for (std::size_t i = 0; i < n; ++i) integrate(data[i].p, data[i].v, kDt);
    benchmark::DoNotOptimize(data);
    benchmark::ClobberMemory();
  }
  set_entity_counters(state, kEntities, kBytesPerEntity);
}

void BM_IterateStreamFloor(benchmark::State& state) {
  MotionFixture& f = motion();
  for (auto _ : state) {
    float* p = f.flat_p.get();
    const float* v = f.flat_v.get();
    const std::size_t n = 3 * kEntities;
    for (std::size_t i = 0; i < n; ++i) p[i] += v[i] * kDt;
    benchmark::DoNotOptimize(p);
    benchmark::ClobberMemory();
  }
  set_entity_counters(state, kEntities, kBytesPerEntity);
}

void BM_IterateQueryChunks(benchmark::State& state) {
  MotionFixture& f = motion();
  for (auto _ : state) {
    const std::size_t chunks = f.query.prepare();
    for (std::size_t c = 0; c < chunks; ++c) {
      const auto view = f.query.chunk(c);
      const std::span<Position> p = view.get<Position>();
      const std::span<const Velocity> v = view.get<const Velocity>();
      for (std::size_t i = 0; i < p.size(); ++i) integrate(p[i], v[i], kDt);
      benchmark::DoNotOptimize(p.data());
    }
    benchmark::ClobberMemory();
  }
  if (f.query.entity_count() != kEntities) state.SkipWithError("query saw the wrong entity count");
  set_entity_counters(state, kEntities, kBytesPerEntity);
}

void BM_IterateQueryEach(benchmark::State& state) {
  MotionFixture& f = motion();
  for (auto _ : state) {
    f.world.query<Position, const Velocity>().each(
        [](Position& p, const Velocity& v) { integrate(p, v, kDt); });
    benchmark::ClobberMemory();
  }
  set_entity_counters(state, kEntities, kBytesPerEntity);
}

void BM_IterateScheduleEach(benchmark::State& state) {
  MotionFixture& f = motion();
  for (auto _ : state) {
    const jobs::FrameStats& stats = f.executor.run(f.schedule, f.world);
    benchmark::DoNotOptimize(stats.frame_ns);
    benchmark::ClobberMemory();
  }
  if (f.executor.last_frame().systems.at(0).entities != kEntities) {
    state.SkipWithError("system saw the wrong entity count");
  }
  set_entity_counters(state, kEntities, kBytesPerEntity);
}

// --- 2. scheduler overhead ------------------------------------------------------------------

void set_frame_counters(benchmark::State& state, const jobs::Schedule& s) {
  state.counters["edges"] = static_cast<double>(edge_count(s));
  state.counters["critical_path"] = static_cast<double>(critical_path(s));
  state.counters["nodes"] = static_cast<double>(s.nodes().size());
  // us per system: inverted iteration-invariant rate of (systems * 1e-6).
  state.counters["us_per_system"] = benchmark::Counter(
      static_cast<double>(kSystems) * 1e-6,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_ScheduleEmpty(benchmark::State& state, int threads) {
  ScheduleFixture& f = sched();
  jobs::Executor& executor = threads == 1 ? f.executor1 : f.executor2;
  jobs::Schedule& schedule = threads == 1 ? f.schedule1 : f.schedule2;
  for (int i = 0; i < 100; ++i) executor.run(schedule, f.world);  // wake the workers
  for (auto _ : state) {
    const jobs::FrameStats& stats = executor.run(schedule, f.world);
    benchmark::DoNotOptimize(stats.frame_ns);
  }
  set_frame_counters(state, schedule);
}

// As above on 2 threads, but with 2 ms of idle time before each frame, as in a game loop
// waiting for vsync: TBB's worker has gone to sleep and must be woken. Manual time: only the
// frame itself is timed.
void BM_ScheduleEmptyIdle(benchmark::State& state) {
  ScheduleFixture& f = sched();
  for (auto _ : state) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const auto t0 = std::chrono::steady_clock::now();
    const jobs::FrameStats& stats = f.executor2.run(f.schedule2, f.world);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(stats.frame_ns);
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
  }
  set_frame_counters(state, f.schedule2);
}

void BM_ScheduleRawDagFloor(benchmark::State& state) {
  ScheduleFixture& f = sched();
  for (int i = 0; i < 100; ++i) f.raw2->run_frame();
  for (auto _ : state) f.raw2->run_frame();
  set_frame_counters(state, f.schedule2);
}

// --- 3. parallel speedup ----------------------------------------------------------------------

void BM_ParallelCompute(benchmark::State& state, int threads) {
  ComputeFixture& f = compute();
  jobs::Executor& executor = threads == 1 ? f.executor1 : f.executor2;
  jobs::Schedule& schedule = threads == 1 ? f.schedule1 : f.schedule2;
  for (int i = 0; i < kWarmupFrames; ++i) executor.run(schedule, f.world);
  for (auto _ : state) {
    const jobs::FrameStats& stats = executor.run(schedule, f.world);
    benchmark::DoNotOptimize(stats.frame_ns);
    benchmark::ClobberMemory();
  }
  set_entity_counters(state, kEntities, sizeof(Position) + sizeof(Phase));
  state.counters["flops_per_entity"] = kFlopsPerEntity;
  state.counters["GFLOPS"] =
      benchmark::Counter(static_cast<double>(kEntities) * kFlopsPerEntity * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate);
}

// ---------------------------------------------------------------------------------------------
// Registration and summary.

constexpr const char* kPlain = "ecs/iterate/plain_vector";
constexpr const char* kStream = "ecs/iterate/stream_floor";
constexpr const char* kChunks = "ecs/iterate/query_chunks";
constexpr const char* kEach = "ecs/iterate/query_each";
constexpr const char* kSchedEach = "ecs/iterate/schedule_each_1t";
constexpr const char* kSched1 = "ecs/schedule/100_empty/threads:1";
constexpr const char* kSched2 = "ecs/schedule/100_empty/threads:2";
constexpr const char* kSchedIdle = "ecs/schedule/100_empty_after_idle/threads:2";
constexpr const char* kRaw2 = "ecs/schedule/raw_tbb_dag_floor/threads:2";
constexpr const char* kCompute1 = "ecs/parallel/logistic_each/threads:1";
constexpr const char* kCompute2 = "ecs/parallel/logistic_each/threads:2";

void register_benchmarks() {
  // Every timing is wall clock: the executors run work on other threads.
  const pb::Timing wall{.unit = benchmark::kMicrosecond, .min_time = kMinTime};
  const pb::Timing wall_1s{.unit = benchmark::kMicrosecond, .min_time = 1.0};
  pb::add(kPlain, wall, BM_IteratePlainVector);
  pb::add(kStream, wall, BM_IterateStreamFloor);
  pb::add(kChunks, wall, BM_IterateQueryChunks);
  pb::add(kEach, wall, BM_IterateQueryEach);
  pb::add(kSchedEach, wall, BM_IterateScheduleEach);
  pb::add(kSched1, wall, BM_ScheduleEmpty, 1);
  pb::add(kSched2, wall, BM_ScheduleEmpty, 2);
  pb::add(kRaw2, wall, BM_ScheduleRawDagFloor);
  pb::add(kSchedIdle,
          {.clock = pb::Timing::Clock::kManual, .unit = benchmark::kMicrosecond, .iterations = 250},
          BM_ScheduleEmptyIdle);
  pb::add(kCompute1, wall_1s, BM_ParallelCompute, 1);
  pb::add(kCompute2, wall_1s, BM_ParallelCompute, 2);
}

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  const double n = static_cast<double>(kEntities);
  auto per_entity = [&](const char* key) { return pb::scale(r.real_ns(key), 1.0 / n); };
  auto us = [&](const char* key) { return pb::scale(r.real_ns(key), 1e-3); };
  auto ms = [&](const char* key) { return pb::scale(r.real_ns(key), 1e-6); };

  // 1. Iteration.
  const auto plain = per_entity(kPlain);
  const auto floor = per_entity(kStream);
  {
    pb::Row row;
    row.name = "iterate 1M: plain vector (baseline)";
    row.unit = "ns/entity";
    row.value = plain;
    row.floor = floor;
    row.floor_ratio = pb::quotient(plain, floor);
    row.note =
        "std::vector<{Position, Velocity}>; floor = flat float arrays, read 24 B + write 12 B "
        "per entity (36 MB/frame logical, 24 MB touched)";
    s.add(row);
  }
  s.add_vs_baseline("iterate 1M: query chunks (1 thr)", "ns/entity", per_entity(kChunks), plain,
                    pb::Goal::ratio_at_least(0.8), floor,
                    "prepared Query, ChunkView get<Position>/get<const Velocity> spans");
  s.add_vs_baseline("iterate 1M: query().each (1 thr)", "ns/entity", per_entity(kEach), plain,
                    pb::Goal::ratio_at_least(0.8), floor, "World::query<>().each(lambda)");
  s.add_vs_baseline("iterate 1M: Schedule add_each (1 thr)", "ns/entity", per_entity(kSchedEach),
                    plain, pb::Goal::ratio_at_least(0.8), floor, "Executor(1).run per frame");

  // 2. Scheduler overhead.
  const auto t1 = us(kSched1);
  const auto t2 = us(kSched2);
  const auto raw = us(kRaw2);
  const auto edges = r.counter(kSched2, "edges");
  const auto path = r.counter(kSched2, "critical_path");
  {
    pb::Row row;
    row.name = "schedule: 100 empty systems (2 thr)";
    row.unit = "us/frame";
    row.value = t2;
    row.baseline = t1;
    row.ratio = pb::quotient(t1, t2);
    row.ratio_def = "baseline/value, baseline = same graph on Executor(1)";
    row.goal = pb::Goal::value_at_most(100);
    row.floor = raw;
    row.floor_ratio = pb::quotient(t2, raw);
    row.note = "floor = same reduced graph on bare tbb::task_group + atomics, empty bodies";
    s.add(row);
  }
  {
    pb::Row row;
    row.name = "schedule: 100 empty, after 2 ms idle (2 thr)";
    row.unit = "us/frame";
    row.value = us(kSchedIdle);
    row.baseline = t2;
    row.ratio = pb::quotient(t2, row.value);
    row.ratio_def = "baseline/value, baseline = back-to-back frames (2 thr)";
    row.floor = raw;
    row.floor_ratio = pb::quotient(row.value, raw);
    row.note = "the frame after a 2 ms sleep (TBB worker asleep, as between vsynced frames)";
    s.add(row);
  }
  {
    pb::Row row;
    row.name = "schedule: 100 empty systems (1 thr)";
    row.unit = "us/frame";
    row.value = t1;
    row.note = "Executor(1) runs nodes in topological order, no tasks";
    s.add(row);
  }
  {
    pb::Row row;
    row.name = "schedule: per-system overhead (2 thr)";
    row.unit = "us/system";
    row.value = pb::scale(t2, 1.0 / kSystems);
    row.baseline = pb::scale(t1, 1.0 / kSystems);
    row.ratio = pb::quotient(row.baseline, row.value);
    row.ratio_def = "baseline/value, baseline = Executor(1)";
    row.floor = pb::scale(raw, 1.0 / kSystems);
    row.floor_ratio = pb::quotient(row.value, row.floor);
    s.add(row);
  }
  {
    pb::Row row;
    row.name = "schedule: graph edges (reduced)";
    row.unit = "edges";
    row.value = edges;
    char note[128];
    std::snprintf(note, sizeof note,
                  "100 nodes, 20 types, each reads 2 writes 1; critical path %.0f nodes",
                  path.value_or(0));
    row.note = note;
    s.add(row);
  }

  // 3. Parallel speedup.
  {
    const auto c1 = ms(kCompute1);
    const auto c2 = ms(kCompute2);
    pb::Row row;
    row.name = "parallel: logistic add_each 1M (2 thr)";
    row.unit = "ms/frame";
    row.value = c2;
    row.baseline = c1;
    row.ratio = pb::quotient(c1, c2);
    row.ratio_def = "speedup t1/t2 (baseline = Executor(1))";
    row.goal = pb::Goal::ratio_at_least(1.7);
    row.floor = pb::scale(c1, 0.5);
    row.floor_ratio = pb::quotient(c2, row.floor);
    char note[128];
    std::snprintf(note, sizeof note, "floor = t1/2 (perfect scaling); %d flops/entity, wall clock",
                  kFlopsPerEntity);
    row.note = note;
    s.add(row);
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  return pb::run_group(argc, argv, "ecs", register_benchmarks, summarize, [] {
    g_compute.reset();
    g_schedule.reset();
    g_motion.reset();
  });
}
