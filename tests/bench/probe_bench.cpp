// Benchmark group "probes": the probe-cloud traversal system (systems/probe_cloud, [Sukys14]
// sec. 3.2, [Cupisz12]) on this machine.
//
//   build/release/tests/bench/bench_probes [--benchmark_* flags] [--summary_out=PATH]
//       [--records_out=PATH.json] [--chart_out=PATH.svg]
//
// This file:
//  - tetrahedralize  delaunay_tetrahedralize on 1k, 10k, 100k points (uniform in a 100 m cube,
//                    clustered: 20 Gaussian clusters of sigma 3 m, grid: 10^3, 22^3, 46^3), wall
//                    clock, against the Debian `tetgen` program on the same points in the same
//                    run: `tetgen -QNEF points.node` (quiet; no .node/.ele/.face output: the
//                    plain Delaunay tetrahedralization, no quality refinement), the process's
//                    wall time (it includes process start and reading the ASCII .node file; a
//                    4-point run shows that overhead). Tetrahedron counts from an untimed
//                    `tetgen -QNF` run (.ele header); equal for points in general position
//                    (unique Delaunay tetrahedralization), different on the grid (cospherical
//                    ties split either way).
//  - frame           ProbeTetWalk::locate_batch (walk from the cached cell + interpolation,
//                    3 bands) for 10,000 and 100,000 entities moving 5 m/s at 60 fps (8 cm per
//                    frame, so the walk starts from the cell it ended in) through a cloud of
//                    10,000 random probes over 100 m x 100 m x 20 m, on 2 threads
//                    (tbb::parallel_for over blocks of 1,024 in a 2-thread arena); only the walk
//                    is timed (manual clock). Baseline: the same frame without a cache (every
//                    entity located by the fallback grid, as after a teleport or a new cloud).
//  - query           the same, one thread, CPU clock, per entity: the Unity anchor's unit.
//  - fma             scalar FMA throughput (8 independent chains), the unit of the floors.
// probe_records.cpp: speed versus accuracy (clouds of the accuracy scene against the reference
// integrator), --records_out (JSON records) and --chart_out (SVG), written atomically.
//
// Floors: operations counted in the code (probe_bench.h), each FMA, compare or subtraction as
// one, times the measured scalar FMA time, divided by the threads: a lower bound on issue
// slots, not a prediction. Bytes touched per cell step and per interpolation are counted too
// (counters, notes), not turned into a floor: the cloud (7 MB here) sits partly in cache.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bench_registry.h"
#include "common/random_draws.h"
#include "penumbra/components/probe_anchor.h"
#include "penumbra/components/probe_lighting.h"
#include "penumbra/components/transform.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/probe_cloud/delaunay_tetrahedralization.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_systems.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"
#include "probe_accuracy_scene.h"
#include "probe_bench.h"

extern char** environ;

namespace penumbra::bench::probes {
namespace {

namespace pb = penumbra::bench;
namespace pc = penumbra::probe_cloud;
namespace acc = penumbra::probe_cloud::accuracy;

constexpr const char* kDistributions[] = {"uniform", "clustered", "grid"};
constexpr int kSizes[] = {1'000, 10'000, 100'000};
constexpr int kEntities[] = {10'000, 100'000};
constexpr std::size_t kBlock = 1024;
constexpr float kSpeed = 5.0f;  // m/s
constexpr float kDt = 1.0f / 60.0f;
constexpr int kBands = 3;

using pb::fmt;

// --- Point sets -----------------------------------------------------------------------------

std::vector<glm::dvec3> point_set(const std::string& dist, int n) {
  std::mt19937 rng(static_cast<std::uint32_t>(n * 7 + dist.size()));
  std::uniform_real_distribution<float> u(0, 100);
  std::vector<glm::vec3> p;
  if (dist == "uniform") {
    for (int i = 0; i < n; ++i) p.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, u));
  } else if (dist == "clustered") {
    std::vector<glm::vec3> centres;
    for (int c = 0; c < 20; ++c) centres.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, u));
    std::normal_distribution<float> g(0, 3);
    std::uniform_int_distribution<int> pick(0, 19);
    for (int i = 0; i < n; ++i) {
      const glm::vec3 offset =
          penumbra::test::draw_zyx<glm::vec3>(rng, g);  // before the pick: GCC's order
      p.push_back(centres[pick(rng)] + offset);
    }
  } else {
    const int s = static_cast<int>(std::lround(std::cbrt(n)));
    const float h = 100.0f / s;
    for (int k = 0; k < s; ++k)
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) p.emplace_back(i * h, j * h, k * h);
  }
  // Float positions (as build_probe_cloud gets them), tetrahedralized as doubles.
  return {p.begin(), p.end()};
}

const std::vector<glm::dvec3>& points_for(const std::string& dist, int n) {
  static std::map<std::pair<std::string, int>, std::vector<glm::dvec3>> cache;
  auto it = cache.find({dist, n});
  if (it == cache.end()) it = cache.emplace(std::pair(dist, n), point_set(dist, n)).first;
  return it->second;
}

// --- tetgen ---------------------------------------------------------------------------------

std::filesystem::path work_dir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("penumbra_bench_probes_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

std::string write_node(const std::vector<glm::dvec3>& pts, const std::string& name) {
  const std::filesystem::path path = work_dir() / (name + ".node");
  std::ofstream f(path);
  f << pts.size() << " 3 0 0\n";
  char line[128];
  for (std::size_t i = 0; i < pts.size(); ++i) {
    std::snprintf(line, sizeof line, "%zu %.17g %.17g %.17g\n", i + 1, pts[i].x, pts[i].y,
                  pts[i].z);
    f << line;
  }
  return path.string();
}

// Runs `tetgen flags node` with stdout to /dev/null; its wall time in seconds (and in `cpu`
// its user + system CPU time), or nothing when it could not run or failed.
std::optional<double> run_tetgen(const std::string& flags, const std::string& node,
                                 double* cpu = nullptr) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  std::string prog = "tetgen", f = flags, n = node;
  char* argv[] = {prog.data(), f.data(), n.data(), nullptr};
  pid_t pid = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = posix_spawnp(&pid, "tetgen", &fa, nullptr, argv, environ);
  int status = 0;
  rusage usage{};
  if (rc == 0) wait4(pid, &status, 0, &usage);
  const auto t1 = std::chrono::steady_clock::now();
  if (cpu)
    *cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  return std::chrono::duration<double>(t1 - t0).count();
}

// tetgen's tetrahedron count for `node` (an untimed run writing only the .ele file).
std::optional<double> tetgen_count(const std::string& node) {
  if (!run_tetgen("-QNF", node)) return std::nullopt;
  std::filesystem::path ele(node);
  ele.replace_extension(".1.ele");
  std::ifstream f(ele);
  double count = 0;
  if (!(f >> count)) return std::nullopt;
  f.close();
  std::filesystem::remove(ele);
  return count;
}

std::string tetra_key(const char* method, const std::string& dist, int n) {
  return std::string("BM_") + method + "/" + dist + "/" + std::to_string(n);
}

void BM_Tetrahedralize(benchmark::State& state, std::string dist, int n) {
  const std::vector<glm::dvec3>& pts = points_for(dist, n);
  std::size_t tets = 0;
  for (auto _ : state) {
    const pc::DelaunayTetrahedralization t = pc::delaunay_tetrahedralize(pts);
    tets = t.finite_count;
    benchmark::DoNotOptimize(t.vertices.data());
  }
  state.counters["points"] = static_cast<double>(pts.size());
  state.counters["tetrahedra"] = static_cast<double>(tets);
  state.counters["tetrahedra_per_point"] = static_cast<double>(tets) / pts.size();
}

void BM_Tetgen(benchmark::State& state, std::string dist, int n) {
  const std::vector<glm::dvec3>& pts = points_for(dist, n);
  const std::string node = write_node(pts, dist + "_" + std::to_string(n));
  const auto count = tetgen_count(node);
  if (!count) {
    state.SkipWithError("tetgen did not run (apt-get install tetgen)");
    for (auto _ : state) {
    }
    return;
  }
  double cpu_total = 0;
  for (auto _ : state) {
    double cpu = 0;
    const auto s = run_tetgen("-QNEF", node, &cpu);
    state.SetIterationTime(s.value_or(0));
    cpu_total += cpu;
  }
  std::filesystem::remove(node);
  // The child's CPU time (the harness's CPU clock sees only this process).
  state.counters["process_cpu_ms"] = 1e3 * cpu_total / static_cast<double>(state.iterations());
  state.counters["points"] = static_cast<double>(pts.size());
  state.counters["tetrahedra"] = *count;
}

// tetgen on 4 points: process start and exit, the overhead inside every tetgen time.
void BM_TetgenOverhead(benchmark::State& state) {
  const std::string node = write_node({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, "overhead");
  for (auto _ : state) {
    const auto s = run_tetgen("-QNEF", node);
    if (!s) {
      state.SkipWithError("tetgen did not run (apt-get install tetgen)");
      break;
    }
    state.SetIterationTime(*s);
  }
}

// --- Walk frames ----------------------------------------------------------------------------

constexpr glm::vec3 kCloudMin{0, 0, 0}, kCloudMax{100, 100, 20};

const pc::ProbeTetWalk& walk_cloud() {
  static const pc::ProbeTetWalk walk = [] {
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> x(kCloudMin.x, kCloudMax.x), y(kCloudMin.y, kCloudMax.y),
        z(kCloudMin.z, kCloudMax.z), s(0, 1);
    std::vector<glm::vec3> p;
    for (int i = 0; i < 10'000; ++i) p.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, x, y, z));
    std::vector<float> sh(p.size() * 3 * kBands * kBands);
    for (float& v : sh) v = s(rng);
    pc::ProbeCloudBuildSettings settings;
    settings.bands = kBands;
    return pc::ProbeTetWalk(
        std::make_shared<const data::ProbeCloud>(pc::build_probe_cloud(p, sh, settings)));
  }();
  return walk;
}

struct Movers {
  std::vector<glm::vec3> p, v;
  std::vector<std::int32_t> cells;
  std::vector<sh::CoeffsRgb<kBands>> out;  // the cloud's bands, as ProbeLighting holds
  glm::vec3 lo, hi;

  Movers(int n, glm::vec3 lo_, glm::vec3 hi_, std::uint32_t seed)
      : cells(n, pc::kNoCell), out(n), lo(lo_), hi(hi_) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0, 1), a(-1, 1);
    for (int i = 0; i < n; ++i) {
      p.push_back(lo + (hi - lo) * penumbra::test::draw_zyx<glm::vec3>(rng, u));
      glm::vec3 d;
      do d = penumbra::test::draw_zyx<glm::vec3>(rng, a);
      while (glm::dot(d, d) > 1 || glm::dot(d, d) < 1e-4f);
      v.push_back(glm::normalize(d) * kSpeed);
    }
  }
  // One frame's move, bouncing off the box.
  void step() {
    for (std::size_t i = 0; i < p.size(); ++i) {
      p[i] += v[i] * kDt;
      for (int k = 0; k < 3; ++k)
        if (p[i][k] < lo[k] || p[i][k] > hi[k]) {
          v[i][k] = -v[i][k];
          p[i][k] = std::clamp(p[i][k], lo[k], hi[k]);
        }
    }
  }
  std::size_t size() const { return p.size(); }
};

// Walks every entity on `threads` threads (tbb blocks of kBlock); returns the fallbacks.
std::size_t walk_frame(const pc::ProbeTetWalk& walk, Movers& m, tbb::task_arena& arena) {
  std::atomic<std::size_t> fallbacks{0};
  const std::span<const glm::vec3> points(m.p);
  const std::span<std::int32_t> cells(m.cells);
  const std::span<sh::CoeffsRgb<kBands>> out(m.out);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m.size(), kBlock),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        fallbacks += walk.locate_batch(points.subspan(r.begin(), r.size()),
                                                       cells.subspan(r.begin(), r.size()),
                                                       out.subspan(r.begin(), r.size()));
                      });
  });
  return fallbacks.load();
}

struct WalkCounts {
  double steps = 0, fallbacks = 0;  // per entity per frame
};

// One more frame, walked entity by entity outside any timing: steps and fallbacks.
WalkCounts count_frame(const pc::ProbeTetWalk& walk, Movers& m) {
  m.step();
  double steps = 0, fallbacks = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const pc::ProbeWalkResult r = walk.locate(m.p[i], m.cells[i]);
    m.cells[i] = r.cell;
    steps += r.steps;
    fallbacks += r.fallback ? 1 : 0;
  }
  return {steps / m.size(), fallbacks / m.size()};
}

void set_walk_counters(benchmark::State& state, const WalkCounts& c, double entities, int bands) {
  const double cells = c.steps + 1;
  state.counters["entities"] = entities;
  state.counters["steps_per_entity"] = c.steps;
  state.counters["fallbacks_per_entity"] = c.fallbacks;
  state.counters["flops_per_entity"] = cells * cell_test_flops() + interpolation_flops(bands);
  state.counters["bytes_per_entity"] = cells * cell_test_bytes() + interpolation_bytes(bands);
  state.counters["flops_per_frame"] =
      entities * (cells * cell_test_flops() + interpolation_flops(bands));
}

void sort_by_cell(Movers& m);

// The traversal system itself: the same entities as BM_Frame (Transform, ProbeAnchor,
// ProbeLighting) in an ECS world, probes.prepare + probes.walk run by jobs::Executor(2); the
// move (writing the transforms) is not timed, Executor::run is.
void BM_System(benchmark::State& state, int entities) {
  const pc::ProbeTetWalk& walk = walk_cloud();
  const glm::vec3 pad(1.0f);
  Movers m(entities, kCloudMin + pad, kCloudMax - pad, 5);
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor(kThreads);
  pc::emplace_probe_cloud_resources(world, walk.cloud_ptr());
  pc::add_probe_cloud_systems(schedule);
  std::vector<ecs::Entity> ids;
  ids.reserve(m.size());
  for (std::size_t i = 0; i < m.size(); ++i)
    ids.push_back(world.create_with(components::Transform{glm::translate(glm::mat4(1.0f), m.p[i])},
                                    components::ProbeAnchor{}, components::ProbeLighting{}));
  executor.run(schedule, world);  // first locate: fills the cache
  for (auto _ : state) {
    m.step();
    for (std::size_t i = 0; i < m.size(); ++i)
      world.get_mut<components::Transform>(ids[i])->world[3] = glm::vec4(m.p[i], 1.0f);
    const auto t0 = std::chrono::steady_clock::now();
    executor.run(schedule, world);
    const auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
  }
  const auto& report = world.resource<const pc::ProbeWalkReport>();
  state.counters["entities"] = static_cast<double>(entities);
  state.counters["steps_per_entity"] =
      static_cast<double>(report.steps) /
      static_cast<double>(std::max<std::size_t>(1, report.entities));
}

// A frame on 2 threads: cached = walk from last frame's cells; else every entity from no cell.
void BM_Frame(benchmark::State& state, int entities, bool cached) {
  const pc::ProbeTetWalk& walk = walk_cloud();
  const glm::vec3 pad(1.0f);
  Movers m(entities, kCloudMin + pad, kCloudMax - pad, 5);
  tbb::task_arena arena(kThreads);
  walk_frame(walk, m, arena);  // first locate: fills the cache
  for (auto _ : state) {
    m.step();
    if (!cached) std::fill(m.cells.begin(), m.cells.end(), pc::kNoCell);
    const auto t0 = std::chrono::steady_clock::now();
    walk_frame(walk, m, arena);
    const auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    benchmark::DoNotOptimize(m.out.data());
  }
  if (!cached) std::fill(m.cells.begin(), m.cells.end(), pc::kNoCell);
  set_walk_counters(state, count_frame(walk, m), entities, kBands);
}

// One thread, per entity (CPU clock; the move is in the timing, a few ns). sorted: the
// entities ordered by their first cell (sort_by_cell).
void BM_Query(benchmark::State& state, bool cached, bool sorted) {
  const pc::ProbeTetWalk& walk = walk_cloud();
  const glm::vec3 pad(1.0f);
  Movers m(10'000, kCloudMin + pad, kCloudMax - pad, 6);
  walk.locate_batch(m.p, m.cells, m.out);
  if (sorted) sort_by_cell(m);
  for (auto _ : state) {
    m.step();
    if (!cached) std::fill(m.cells.begin(), m.cells.end(), pc::kNoCell);
    walk.locate_batch(m.p, m.cells, m.out);
    benchmark::DoNotOptimize(m.out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(m.size()));
  if (!cached) std::fill(m.cells.begin(), m.cells.end(), pc::kNoCell);
  set_walk_counters(state, count_frame(walk, m), static_cast<double>(m.size()), kBands);
}

// --- Speed versus accuracy (the accuracy scene, tests/probe_cloud/probe_accuracy_scene.h) ----

struct SweepFixture {
  data::EnvironmentMap sky = acc::lobe_sky();
  reference::Scene scene = acc::make_scene(sky);
  acc::Queries queries = acc::make_queries(scene, 800, 4096, 2024);
};

const SweepFixture& sweep_fixture() {
  static const SweepFixture f;
  return f;
}

std::vector<glm::vec3> sweep_points(const SweepCase& c) {
  if (c.spacing > 0) return acc::grid_points(c.spacing);
  if (c.cloud == "random 400") return acc::random_points(400, 99);
  return acc::hand_placed_points();
}

// A frame of kSweepEntities entities moving through the accuracy scene's volume, 2 threads; the
// counters: the interpolated irradiance against the reference (acc::cloud_errors, the
// accuracy test's numbers), computed outside the timing.
void BM_Sweep(benchmark::State& state, SweepCase c) {
  const SweepFixture& f = sweep_fixture();
  const pc::ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(
      acc::make_cloud(f.scene, sweep_points(c), c.bands, c.windowed)));
  Movers m(kSweepEntities, acc::kVolumeMin, acc::kVolumeMax, 7);
  tbb::task_arena arena(kThreads);
  walk_frame(walk, m, arena);
  for (auto _ : state) {
    m.step();
    const auto t0 = std::chrono::steady_clock::now();
    walk_frame(walk, m, arena);
    const auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    benchmark::DoNotOptimize(m.out.data());
  }
  set_walk_counters(state, count_frame(walk, m), kSweepEntities, c.bands);
  const acc::CloudErrors e = acc::cloud_errors(walk.cloud(), f.queries);
  state.counters["probes"] = static_cast<double>(e.probes);
  state.counters["tetrahedra"] = static_cast<double>(e.tetrahedra);
  state.counters["rel_rms_vs_reference"] = e.all.rel_rms;
  state.counters["max_rel_vs_reference"] = e.all.max_rel;
  state.counters["reference_rel_se"] = e.all.noise;
  for (int k = 0; k < 3; ++k)
    state.counters[std::string("rel_rms_") + acc::kRegionNames[k]] = e.region[k].rel_rms;
}

// The entities of BM_Query sorted by their first cell (the cloud's cells follow the
// tetrahedralizer's spatial insertion order), so that neighbours in memory walk nearby cells.
void sort_by_cell(Movers& m) {
  std::vector<std::size_t> order(m.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return m.cells[a] < m.cells[b]; });
  Movers sorted = m;
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted.p[i] = m.p[order[i]];
    sorted.v[i] = m.v[order[i]];
    sorted.cells[i] = m.cells[order[i]];
  }
  m = std::move(sorted);
}

// The memory the walk touches, alone: per entity, its cached cell's hot record (one line:
// transform and vertices, ProbeTetWalk::hot()), then one float per cache line of the four
// probes' records (SH and position), in the same order as BM_Query. The same-run floor of the
// query's memory traffic at this access pattern (no arithmetic).
void BM_Touch(benchmark::State& state, bool sorted) {
  const pc::ProbeTetWalk& walk = walk_cloud();
  const pc::detail::ProbeHotData& hot = walk.hot();
  const glm::vec3 pad(1.0f);
  Movers m(10'000, kCloudMin + pad, kCloudMax - pad, 6);
  walk.locate_batch(m.p, m.cells, m.out);
  if (sorted) sort_by_cell(m);
  const std::size_t per_probe = hot.sh_count + 3;
  float sum = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < m.size(); ++i) {
      const pc::detail::ProbeHotCell& cell = hot.cells[static_cast<std::size_t>(m.cells[i])];
      sum += cell.transform[9] + m.p[i].x;
      for (std::int32_t v : cell.vertices) {
        if (v < 0) continue;
        const float* r = hot.probe(static_cast<std::size_t>(v));
        for (std::size_t k = 0; k < per_probe; k += 16) sum += r[k];
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(m.size()));
}

std::string frame_key(int entities, bool cached) {
  return "BM_Frame/" + std::to_string(entities) + (cached ? "/walk" : "/no_cache");
}

void register_benchmarks() {
  const pb::Timing cpu{.clock = pb::Timing::Clock::kCpu, .unit = benchmark::kMicrosecond};
  pb::add("BM_FmaThroughput", cpu, pb::BM_FmaThroughput);
  for (const char* d : kDistributions)
    for (int n : kSizes) {
      const bool big = n >= 100'000;
      const pb::Timing ours{.unit = benchmark::kMillisecond,
                            .iterations = big ? 1 : (n >= 10'000 ? 5 : 50),
                            .repetitions = big ? 3 : 5};
      pb::Timing theirs = ours;
      theirs.clock = pb::Timing::Clock::kManual;
      theirs.iterations = big ? 1 : (n >= 10'000 ? 3 : 10);
      pb::add(tetra_key("Tetrahedralize", d, n), ours, BM_Tetrahedralize, std::string(d), n);
      pb::add(tetra_key("Tetgen", d, n), theirs, BM_Tetgen, std::string(d), n);
    }
  pb::add("BM_TetgenOverhead",
          {.clock = pb::Timing::Clock::kManual, .unit = benchmark::kMillisecond, .iterations = 20},
          BM_TetgenOverhead);
  const pb::Timing frame{.clock = pb::Timing::Clock::kManual,
                         .unit = benchmark::kMillisecond,
                         .iterations = 60,
                         .repetitions = 5};
  for (int n : kEntities)
    for (bool cached : {true, false}) {
      pb::Timing t = frame;
      if (n >= 100'000 || !cached) t.iterations = 10;
      pb::add(frame_key(n, cached), t, BM_Frame, n, cached);
    }
  for (int n : kEntities) {
    pb::Timing t = frame;
    if (n >= 100'000) t.iterations = 10;
    pb::add("BM_System/" + std::to_string(n), t, BM_System, n);
  }
  const pb::Timing query{
      .clock = pb::Timing::Clock::kCpu, .unit = benchmark::kMicrosecond, .repetitions = 3};
  pb::add("BM_Query/walk", query, BM_Query, true, false);
  pb::add("BM_Query/no_cache", query, BM_Query, false, false);
  pb::add("BM_Query/walk_sorted", query, BM_Query, true, true);
  pb::add("BM_Touch/unsorted", query, BM_Touch, false);
  pb::add("BM_Touch/sorted", query, BM_Touch, true);
  register_sweep_benchmarks();
}

// --- Summary --------------------------------------------------------------------------------

std::optional<double> cpu_ns(const pb::Results& r, const std::string& key) {
  if (auto m = r.get(key)) return m->cpu_ns;
  return std::nullopt;
}
std::optional<double> ms(const pb::Results& r, const std::string& key) {
  return pb::scale(r.real_ns(key), 1e-6);
}

pb::Row& add_row(pb::Summary& s, std::string name, std::string unit, std::optional<double> value,
                 std::optional<double> baseline, pb::Goal goal, std::optional<double> floor,
                 std::string note) {
  pb::Row& row = s.add_vs_baseline(std::move(name), std::move(unit), value, baseline, goal, floor,
                                   std::move(note));
  if (!baseline) row.ratio_def.clear();
  return row;
}

std::optional<double> floor_ms(const pb::Results& r, const std::string& key, double ns_per_fma,
                               double threads) {
  const auto flops = r.counter(key, "flops_per_frame");
  if (!flops || !(ns_per_fma > 0)) return std::nullopt;
  return *flops * ns_per_fma / threads * 1e-6;
}

std::string size_text(int n) {
  return n >= 1000 ? std::to_string(n / 1000) + "k" : std::to_string(n);
}

pb::Summary summarize(const pb::Results& r, const Outputs& out) {
  pb::Summary s;
  const double ns_per_fma = pb::add_fma_floor_row(
      r, s, "8 independent chains; floors = counted operations x this / threads");

  for (const char* d : kDistributions)
    for (int n : kSizes) {
      const std::string ours = tetra_key("Tetrahedralize", d, n),
                        theirs = tetra_key("Tetgen", d, n);
      const auto t_ours = r.counter(ours, "tetrahedra"), t_theirs = r.counter(theirs, "tetrahedra");
      std::string counts = "tetrahedra " + fmt("%.0f", t_ours.value_or(NAN)) + ", tetgen " +
                           fmt("%.0f", t_theirs.value_or(NAN));
      if (t_ours && t_theirs)
        counts += *t_ours == *t_theirs
                      ? " (equal)"
                      : (std::string(d) == "grid" ? " (differ: cospherical ties)" : " (DIFFER)");
      const auto net =
          pb::quotient(pb::scale(ms(r, theirs), 1.0).has_value() && ms(r, "BM_TetgenOverhead")
                           ? std::optional<double>(*ms(r, theirs) - *ms(r, "BM_TetgenOverhead"))
                           : std::nullopt,
                       ms(r, ours));
      counts += "; tetgen net of its 4-point run / ours = " + fmt("%.2f", net.value_or(NAN));
      const auto our_cpu = pb::scale(cpu_ns(r, ours), 1e-6);
      counts +=
          "; CPU time: tetgen " + fmt("%.1f", r.counter(theirs, "process_cpu_ms").value_or(NAN)) +
          " ms, ours " + fmt("%.1f", our_cpu.value_or(NAN)) + " ms, ratio " +
          fmt("%.2f", pb::quotient(r.counter(theirs, "process_cpu_ms"), our_cpu).value_or(NAN));
      add_row(s,
              std::string("tetrahedralize ") + d + " " + size_text(n) + " (" +
                  fmt("%.0f", r.counter(ours, "points").value_or(n)) + " points)",
              "ms", ms(r, ours), ms(r, theirs), pb::Goal::ratio_at_least(1), std::nullopt,
              "baseline: tetgen -QNEF, same points, same run (process wall time, "
              "start + .node read included); " +
                  counts);
    }
  add_row(s, "tetgen process overhead (4 points)", "ms", ms(r, "BM_TetgenOverhead"), std::nullopt,
          pb::Goal::none(), std::nullopt, "start, read, exit: inside every tetgen time above");

  for (int n : kEntities) {
    const std::string k = frame_key(n, true), base = frame_key(n, false);
    const auto steps = r.counter(k, "steps_per_entity");
    const auto bytes = r.counter(k, "bytes_per_entity");
    add_row(s, "frame: " + size_text(n) + " moving entities, walk + interpolation, 2 threads", "ms",
            ms(r, k), ms(r, base), pb::Goal::none(), floor_ms(r, k, ns_per_fma, kThreads),
            "baseline: no cache (fallback grid locate for all); " +
                fmt("%.2f", steps.value_or(NAN)) + " steps per entity, " +
                fmt("%.0f", bytes.value_or(NAN)) + " bytes touched per entity (" +
                fmt("%.0f", cell_test_bytes()) + " per cell tested, " +
                fmt("%.0f", interpolation_bytes(kBands)) + " per interpolation); 10,000 probes, " +
                std::to_string(kBands) + " bands");
  }
  for (int n : kEntities) {
    const std::string k = "BM_System/" + std::to_string(n);
    add_row(s, "system: probes.walk, " + size_text(n) + " moving entities, Executor(2)", "ms",
            ms(r, k), ms(r, frame_key(n, true)), pb::Goal::none(),
            floor_ms(r, frame_key(n, true), ns_per_fma, kThreads),
            "the ECS system (Transform -> ProbeAnchor, ProbeLighting) on the job graph; baseline: "
            "the locate_batch frame above, same entities");
  }
  const auto per_query = pb::scale(cpu_ns(r, "BM_Query/walk"), 1e-4);  // ns per entity
  const auto per_fresh = pb::scale(cpu_ns(r, "BM_Query/no_cache"), 1e-4);
  const double q_flops = r.counter("BM_Query/walk", "flops_per_entity").value_or(0);
  add_row(s, "query: walk + interpolation, 1 thread", "ns", per_query, per_fresh, pb::Goal::none(),
          q_flops * ns_per_fma,
          "per moving entity; baseline: without a cache; floor: " + fmt("%.0f", q_flops) +
              " counted ops (" + fmt("%.0f", cell_test_flops()) + " per cell tested, " +
              fmt("%.0f", interpolation_flops(kBands)) + " per interpolation)");
  const auto per_sorted = pb::scale(cpu_ns(r, "BM_Query/walk_sorted"), 1e-4);
  const auto touch = pb::scale(cpu_ns(r, "BM_Touch/unsorted"), 1e-4);
  const auto touch_sorted = pb::scale(cpu_ns(r, "BM_Touch/sorted"), 1e-4);
  add_row(s, "query: memory touched alone (cell record, 4 probe records)", "ns", touch, per_query,
          pb::Goal::none(), std::nullopt,
          "same entities and order as the query, loads only; ratio: the query / this");
  add_row(s, "query: entities sorted by cell, 1 thread", "ns", per_sorted, per_query,
          pb::Goal::none(), q_flops * ns_per_fma,
          "baseline: unsorted (the rows above); memory touched alone, sorted: " +
              fmt("%.1f ns", touch_sorted.value_or(NAN)));
  // Anchor: [Cupisz12], Unity: 2,000 queries in under 1 ms on an iPad 2 (one core).
  add_row(s, "anchor: 2,000 queries, 1 thread (Unity: < 1 ms on an iPad 2)", "ms",
          pb::scale(per_query, 2000 * 1e-6), 1.0, pb::Goal::value_at_most(1.0), std::nullopt,
          "ratio: the anchor's 1 ms / ours");
  const std::string goal_key = "BM_System/10000";
  add_row(s, "goal: 10,000 entities per frame, 2 threads (the system)", "ms", ms(r, goal_key),
          std::nullopt, pb::Goal::value_at_most(kGoalMs),
          floor_ms(r, frame_key(10'000, true), ns_per_fma, kThreads),
          "issue 12: <= 0.5 ms; measured / goal = " +
              fmt("%.2fx", pb::quotient(ms(r, goal_key), kGoalMs).value_or(NAN)));
  write_records(r, ns_per_fma, out);
  return s;
}

}  // namespace

const std::vector<SweepCase>& sweep_cases() {
  static const std::vector<SweepCase> cases = [] {
    std::vector<SweepCase> out;
    const auto grid = [](float spacing, int bands) {
      SweepCase c;
      c.cloud = "grid " + fmt("%g", spacing) + " m";
      c.spacing = spacing;
      c.bands = bands;
      c.key = "BM_Sweep/grid_" + fmt("%g", spacing) + "m/bands:" + std::to_string(bands);
      return c;
    };
    for (float spacing : {2.0f, 1.0f, 0.5f}) out.push_back(grid(spacing, 3));
    out.push_back(grid(1.0f, 2));
    out.push_back(grid(1.0f, 4));
    out.push_back(grid(0.5f, 2));
    for (float spacing : {1.0f, 0.5f}) {
      SweepCase c = grid(spacing, 3);
      c.cloud += ", windowed";
      c.key += "/windowed";
      c.windowed = true;
      out.push_back(c);
    }
    out.push_back({"BM_Sweep/random_400/bands:3", "random 400", 0, 3});
    out.push_back({"BM_Sweep/hand_placed/bands:3", "hand-placed", 0, 3});
    return out;
  }();
  return cases;
}

void register_sweep_benchmarks() {
  const pb::Timing t{.clock = pb::Timing::Clock::kManual,
                     .unit = benchmark::kMillisecond,
                     .iterations = 30,
                     .repetitions = 3};
  for (const SweepCase& c : sweep_cases()) pb::add(c.key, t, BM_Sweep, c);
}

std::vector<CaseInfo> bench_cases() {
  std::vector<CaseInfo> out;
  for (const char* d : kDistributions)
    for (int n : kSizes) {
      out.push_back({tetra_key("Tetrahedralize", d, n), "tetrahedralize", d, "ours",
                     tetra_key("Tetgen", d, n), static_cast<double>(n), 0, std::nullopt});
      out.push_back({tetra_key("Tetgen", d, n), "tetrahedralize", d, "tetgen", "",
                     static_cast<double>(n), 0, std::nullopt});
    }
  for (int n : kEntities)
    out.push_back({"BM_System/" + std::to_string(n), "frame", "random 10,000 probes", "system",
                   frame_key(n, true), static_cast<double>(n), kBands,
                   kGoalMs * n / kGoalEntities});
  for (int n : kEntities)
    for (bool cached : {true, false})
      out.push_back({frame_key(n, cached), "frame", "random 10,000 probes",
                     cached ? "walk" : "no_cache", cached ? frame_key(n, false) : "",
                     static_cast<double>(n), kBands,
                     cached ? std::optional<double>(kGoalMs * n / kGoalEntities) : std::nullopt});
  return out;
}

}  // namespace penumbra::bench::probes

int main(int argc, char** argv) {
  namespace pp = penumbra::bench::probes;
  pp::Outputs out;
  out.records_path = penumbra::bench::take_flag(argc, argv, "records_out");
  out.chart_path = penumbra::bench::take_flag(argc, argv, "chart_out");
  const int status = penumbra::bench::run_group(
      argc, argv, "probes", pp::register_benchmarks,
      [&](const penumbra::bench::Results& r) { return pp::summarize(r, out); });
  std::error_code ec;
  std::filesystem::remove_all(pp::work_dir(), ec);
  return status;
}
