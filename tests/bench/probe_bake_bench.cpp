// The probe_bake benchmark group (issue 14, docs/probe_bake.md "Benchmarks"):
//  - the bake of scenes/room.json and scenes/valley.json at their default settings (grid
//    placement at the scene's spacing, 1,024 samples, validity, no edge rays; TBB's default
//    thread count): time per probe and per ray, probes, rays, rays per second;
//  - the floor: the reference integrator's bare ray rate (reference::Scene::occluded and
//    first_hit on random rays in the same scene, origins uniform in the probe volume, directions
//    uniform on the sphere), on 1 and 2 threads; the summary divides the bake's rays/s by it;
//  - placement per method on the room (grid_points; spawn and merge, gradient ascent with small
//    caps, timed as the bake's own placement_seconds) and edge rays alone (one round of
//    edge_ray_points over the 1 m and 1.5 m grids);
//  - the placement sweep, speed against accuracy ([Sukys14] sec. 3.1; the cases of the test
//    RoomAccuracy.ErrorVersusProbeCount, probe_bake_records.h): the room baked per method (grid
//    2-0.75 m, spawn-merge from 2 and 1 m, gradient from 1.5-0.75 m; 512 samples, validity on,
//    edge rays where the case names them), timed (bake wall time, placement time), its interpolated
//    irradiance against the reference integrator at the accuracy tests' points (tests/probe_bake/
//    room_accuracy_points.h; reference values computed once per run): rel. RMS error in free
//    space, the dark-side leak metric, the lit side, probes.
// --records_out writes one JSON record per case and per sweep point, --chart_out the sweep's
// chart (bake time, log, against rel. RMS error; probe_bake_records.cpp), both atomically.
//
//   build/release/tests/bench/bench_probe_bake --benchmark_out=build/bench/probe_bake_gbench.json
//       --benchmark_out_format=json --summary_out=build/bench/probe_bake_summary.json
//       --records_out=build/bench/probe_bake.json --chart_out=build/bench/probe_bake.svg
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "bench_json.h"
#include "bench_registry.h"
#include "common/random_draws.h"
#include "penumbra/reference/scene.h"
#include "penumbra/systems/probe_bake/bake_scene.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "penumbra/systems/probe_bake/probe_edge_rays.h"
#include "penumbra/systems/probe_bake/probe_placement.h"
#include "probe_bake_records.h"
#include "room_accuracy_points.h"

namespace pb = penumbra::bench;
namespace bake = penumbra::probe_bake;
namespace ref = penumbra::reference;
namespace pbr = penumbra::bench::probe_bake;
namespace acc = penumbra::probe_bake::accuracy;

namespace {

const std::filesystem::path kRoot = PENUMBRA_SOURCE_DIR;
const std::filesystem::path kData = kRoot / ".." / "shared" / "data";
constexpr float kInf = std::numeric_limits<float>::infinity();

// A scene loaded once, with its ray tracer and a fixed set of random rays.
struct LoadedScene {
  bake::BakeScene scene;
  std::unique_ptr<ref::Scene> traced;
  std::vector<glm::vec3> origins, dirs;
};

constexpr std::size_t kRays = 1 << 16;

const LoadedScene& scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<LoadedScene>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<LoadedScene>();
    slot->scene = bake::load_bake_scene(kRoot / "scenes" / (name + ".json"), kData);
    slot->traced = std::make_unique<ref::Scene>(slot->scene.desc);
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const bake::ProbeVolume& v = slot->scene.volume;
    slot->origins.reserve(kRays);
    slot->dirs.reserve(kRays);
    for (std::size_t i = 0; i < kRays; ++i) {
      slot->origins.push_back(v.min +
                              (v.max - v.min) * penumbra::test::draw_zyx<glm::vec3>(rng, u));
      const float z = 2.0f * u(rng) - 1.0f, phi = 6.2831853f * u(rng);
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      slot->dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return *slot;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------------------------------------
// The bake at the scene's defaults.

void BM_Bake(benchmark::State& state, std::string name) {
  const LoadedScene& s = scene(name);
  bake::BakeSettings settings;
  double seconds = 0, capture_seconds = 0;
  std::uint64_t rays = 0;
  std::size_t probes = 0, placed = 0;
  for (auto _ : state) {
    bake::BakeReport report;
    const auto t0 = std::chrono::steady_clock::now();
    auto cloud = bake::bake_probe_cloud(s.scene, settings, &report);
    seconds += seconds_since(t0);
    benchmark::DoNotOptimize(cloud);
    if (!report.valid_cloud) state.SkipWithError("the baked cloud is not valid");
    capture_seconds += report.capture_seconds + report.validity_seconds;
    rays += report.rays;
    probes += report.probes.size();
    placed += report.placed;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["probes"] = static_cast<double>(probes) / n;
  state.counters["placed"] = static_cast<double>(placed) / n;
  state.counters["rays"] = static_cast<double>(rays) / n;
  state.counters["rays_per_probe"] = static_cast<double>(rays) / static_cast<double>(probes);
  state.counters["us_per_probe"] = seconds * 1e6 / static_cast<double>(probes);
  state.counters["ns_per_ray"] = seconds * 1e9 / static_cast<double>(rays);
  state.counters["rays_per_s"] = static_cast<double>(rays) / seconds;
  state.counters["capture_rays_per_s"] = static_cast<double>(rays) / capture_seconds;
}

// ---------------------------------------------------------------------------------------------
// The floor: bare rays through the reference integrator's scene, each benchmark thread tracing
// its share of the fixed random rays.

template <bool kFirstHit>
void BM_Rays(benchmark::State& state, std::string name) {
  const LoadedScene& s = scene(name);
  const std::size_t per_thread = kRays / static_cast<std::size_t>(state.threads());
  const std::size_t begin = per_thread * static_cast<std::size_t>(state.thread_index());
  std::size_t hits = 0;
  for (auto _ : state) {
    for (std::size_t i = begin; i < begin + per_thread; ++i) {
      if constexpr (kFirstHit) {
        const ref::Hit h = s.traced->first_hit(s.origins[i], s.dirs[i], kInf);
        hits += h.distance < kInf ? 1 : 0;
      } else {
        hits += s.traced->occluded(s.origins[i], s.dirs[i], kInf) ? 1 : 0;
      }
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(per_thread));
  state.counters["rays_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * per_thread), benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = benchmark::Counter(
      static_cast<double>(hits) / static_cast<double>(state.iterations() * per_thread),
      benchmark::Counter::kAvgThreads);
}

// ---------------------------------------------------------------------------------------------
// Placement on the room.

void BM_PlaceGrid(benchmark::State& state) {
  const LoadedScene& s = scene("room");
  bake::ProbeVolume v = s.scene.volume;
  v.spacing = static_cast<float>(state.range(0)) / 100.0f;
  std::size_t n = 0;
  for (auto _ : state) {
    auto points = bake::grid_points(v);
    n = points.size();
    benchmark::DoNotOptimize(points);
  }
  state.counters["probes"] = static_cast<double>(n);
}

// Spawn and merge or gradient ascent through the bake (their captures are the bake's), from the
// 1.5 m grid with small caps; manual time = the bake's placement_seconds.
void BM_PlaceAdaptive(benchmark::State& state, bake::PlacementMethod method) {
  const LoadedScene& s = scene("room");
  bake::BakeSettings settings;
  settings.spacing = 1.5f;
  settings.samples = 256;
  settings.placement = method;
  settings.spawn_merge.max_iterations = 2;
  settings.spawn_merge.max_probes = 500;
  settings.gradient.max_iterations = 3;
  bake::BakeReport report;
  for (auto _ : state) {
    report = bake::BakeReport{};
    auto cloud = bake::bake_probe_cloud(s.scene, *s.traced, settings, &report);
    benchmark::DoNotOptimize(cloud);
    state.SetIterationTime(report.placement_seconds);
  }
  state.counters["initial"] = static_cast<double>(report.adaptive.initial);
  state.counters["placed"] = static_cast<double>(report.placed);
  state.counters["iterations"] = report.adaptive.iterations;
  state.counters["captured"] = static_cast<double>(report.adaptive.captured);
  state.counters["placement_rays"] = static_cast<double>(report.placement_rays);
  state.counters["placement_rays_per_s"] =
      static_cast<double>(report.placement_rays) / report.placement_seconds;
  state.counters["us_per_capture"] =
      report.placement_seconds * 1e6 / static_cast<double>(report.adaptive.captured);
}

// One round of edge rays over the room's grid at range(0) cm (tetrahedralization included).
void BM_EdgeRays(benchmark::State& state) {
  const LoadedScene& s = scene("room");
  bake::ProbeVolume v = s.scene.volume;
  v.spacing = static_cast<float>(state.range(0)) / 100.0f;
  const std::vector<glm::vec3> points = bake::grid_points(v);
  bake::EdgeRaySettings settings;
  settings.enabled = true;
  settings.max_iterations = 1;
  bake::EdgeRayStats stats;
  for (auto _ : state) {
    stats = bake::EdgeRayStats{};
    auto added = bake::edge_ray_points(s.scene, *s.traced, points, settings, &stats);
    benchmark::DoNotOptimize(added);
  }
  state.counters["probes"] = static_cast<double>(points.size());
  state.counters["edges"] = static_cast<double>(stats.edges);
  state.counters["hits"] = static_cast<double>(stats.hits);
  state.counters["added"] = static_cast<double>(stats.added);
  state.counters["rays_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * stats.edges * 2), benchmark::Counter::kIsRate);
}

// ---------------------------------------------------------------------------------------------
// The placement sweep: the room per method, against the reference at the accuracy tests' points.

// The three point sets of the room with their reference values, computed once per run (the
// reference integrator's bounce at 1,024 samples is the expensive part).
double g_reference_seconds = -1;
const std::array<acc::PointSet, 3>& room_reference() {
  static const std::array<acc::PointSet, 3> sets = [] {
    const LoadedScene& s = scene("room");
    const auto t0 = std::chrono::steady_clock::now();
    auto out = acc::room_point_sets(s.scene, *s.traced);
    g_reference_seconds = seconds_since(t0);
    return out;
  }();
  return sets;
}

void BM_PlacementSweep(benchmark::State& state, pbr::SweepCase c) {
  const LoadedScene& s = scene("room");
  const auto& sets = room_reference();
  bake::BakeSettings settings;  // as RoomAccuracy.ErrorVersusProbeCount
  settings.samples = pbr::kSweepSamples;
  settings.spacing = c.spacing;
  settings.validity = true;
  settings.edge_rays.enabled = c.edge_rays;
  if (c.method.starts_with("spawn-merge")) {
    settings.placement = bake::PlacementMethod::kSpawnMerge;
    settings.spawn_merge.spawn_contrast = c.spawn;
  } else if (c.method.starts_with("gradient")) {
    settings.placement = bake::PlacementMethod::kGradient;
  }
  penumbra::data::ProbeCloud cloud;
  bake::BakeReport report;
  for (auto _ : state) {
    report = bake::BakeReport{};
    const auto t0 = std::chrono::steady_clock::now();
    cloud = bake::bake_probe_cloud(s.scene, *s.traced, settings, &report);
    state.SetIterationTime(seconds_since(t0));
  }
  if (!report.valid_cloud) state.SkipWithError("the baked cloud is not valid");
  state.counters["probes"] = static_cast<double>(cloud.probe_count());
  state.counters["placed"] = static_cast<double>(report.placed);
  state.counters["placement_ms"] = report.placement_seconds * 1e3;
  state.counters["rays"] = static_cast<double>(report.rays);
  state.counters["placement_rays"] = static_cast<double>(report.placement_rays);
  state.counters["rel_rms_error"] = acc::set_error(cloud, sets[acc::kFree]);
  state.counters["dark_side"] = acc::set_error(cloud, sets[acc::kDarkSide]);
  state.counters["lit_side"] = acc::set_error(cloud, sets[acc::kLitSide]);
  if (c.method != "grid") state.counters["iterations"] = report.adaptive.iterations;
}

void register_benchmarks() {
  using Clock = pb::Timing::Clock;
  const pb::Timing bake_timing{
      .clock = Clock::kWall, .unit = benchmark::kMillisecond, .iterations = 1, .repetitions = 3};
  for (const std::string name : {"room", "valley"}) {
    pb::add("BM_Bake/" + name, bake_timing, BM_Bake, name);
    const pb::Timing ray_timing{.clock = Clock::kWall, .unit = benchmark::kMillisecond};
    pb::add("BM_RaysOccluded/" + name, ray_timing, BM_Rays<false>, name)->Threads(1)->Threads(2);
    pb::add("BM_RaysFirstHit/" + name, ray_timing, BM_Rays<true>, name)->Threads(1)->Threads(2);
  }
  pb::add("BM_PlaceGrid", {.clock = Clock::kCpu, .unit = benchmark::kMicrosecond}, BM_PlaceGrid)
      ->Arg(100)
      ->Arg(25);
  const pb::Timing place_timing{
      .clock = Clock::kManual, .unit = benchmark::kMillisecond, .iterations = 1, .repetitions = 3};
  pb::add("BM_PlaceSpawnMerge", place_timing, BM_PlaceAdaptive, bake::PlacementMethod::kSpawnMerge);
  pb::add("BM_PlaceGradient", place_timing, BM_PlaceAdaptive, bake::PlacementMethod::kGradient);
  pb::add("BM_EdgeRays", {.clock = Clock::kWall, .unit = benchmark::kMillisecond}, BM_EdgeRays)
      ->Arg(150)
      ->Arg(100);
  const pb::Timing sweep_timing{.clock = Clock::kManual,
                                .unit = benchmark::kMillisecond,
                                .iterations = 1,
                                .repetitions = pbr::kSweepRepetitions};
  for (const pbr::SweepCase& c : pbr::sweep_cases())
    pb::add(c.key, sweep_timing, BM_PlacementSweep, c);
}

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  for (const std::string name : {"room", "valley"}) {
    const std::string bk = "BM_Bake/" + name;
    const auto bake_rate = r.counter(bk, "rays_per_s");
    const auto capture_rate = r.counter(bk, "capture_rays_per_s");
    s.add_vs_baseline(name + ": bake, time per probe", "us", r.counter(bk, "us_per_probe"),
                      std::nullopt, pb::Goal::none(), std::nullopt,
                      "grid at the scene's spacing, 1,024 samples, validity; wall clock");
    s.add_vs_baseline(name + ": bake, time per ray", "ns", r.counter(bk, "ns_per_ray"),
                      std::nullopt, pb::Goal::none());
    for (const char* threads : {"threads:1", "threads:2"}) {
      const auto floor_rate = r.counter("BM_RaysFirstHit/" + name + "/" + threads, "rays_per_s");
      const auto occluded_rate = r.counter("BM_RaysOccluded/" + name + "/" + threads, "rays_per_s");
      // Rates: ratio = value / floor rate, the share of the bare ray rate the bake reaches.
      pb::Row row;
      row.name = name + ": bake rays/s vs first_hit " + threads;
      row.unit = "rays/s";
      row.value = bake_rate;
      row.baseline = floor_rate;
      row.ratio = (bake_rate && floor_rate && *floor_rate > 0)
                      ? std::optional<double>(*bake_rate / *floor_rate)
                      : std::nullopt;
      row.ratio_def = "value/baseline";
      row.note = "baseline: reference::Scene::first_hit, random rays in the probe volume";
      s.add(row);
      pb::Row occ = row;
      occ.name = name + ": bake capture rays/s vs occluded " + threads;
      occ.value = capture_rate;
      occ.baseline = occluded_rate;
      occ.ratio = (capture_rate && occluded_rate && *occluded_rate > 0)
                      ? std::optional<double>(*capture_rate / *occluded_rate)
                      : std::nullopt;
      occ.note = "capture + validity time only; baseline: reference::Scene::occluded";
      s.add(occ);
    }
  }
  for (const char* m : {"BM_PlaceSpawnMerge", "BM_PlaceGradient"}) {
    s.add_vs_baseline(std::string("room: placement ") + (m + 8), "ms",
                      pb::scale(r.real_ns(m), 1e-6), std::nullopt, pb::Goal::none(), std::nullopt,
                      "from the 1.5 m grid, 256 samples, small caps");
  }
  s.add_vs_baseline("room: edge rays, one round at 1 m", "ms",
                    pb::scale(r.real_ns("BM_EdgeRays/100"), 1e-6), std::nullopt, pb::Goal::none());
  return s;
}

// ---------------------------------------------------------------------------------------------
// Records (--records_out) and the chart (--chart_out): one record per case and sweep point.

struct Outputs {
  std::string records_path, chart_path;
};

std::string json_params(const std::vector<std::pair<std::string, std::string>>& kv) {
  std::string o = "{";
  for (std::size_t i = 0; i < kv.size(); ++i)
    o += (i ? ", " : "") + penumbra::bench_json::jstr(kv[i].first) + ": " + kv[i].second;
  return o + "}";
}

std::vector<pbr::Record> collect(const pb::Results& r) {
  using penumbra::bench_json::compact;
  using penumbra::bench_json::jstr;
  std::vector<pbr::Record> out;
  auto add = [&](const std::string& key, const std::string& kind, const std::string& scene_name,
                 const std::string& method, std::string params) -> pbr::Record* {
    const auto m = r.get(key);
    if (!m) return nullptr;
    pbr::Record rec;
    rec.key = key;
    rec.kind = kind;
    rec.scene = scene_name;
    rec.method = method;
    rec.params_json = std::move(params);
    rec.ms = m->real_ns * 1e-6;
    rec.counters = m->counters;
    if (auto it = m->counters.find("probes"); it != m->counters.end()) rec.probes = it->second;
    if (auto it = m->counters.find("rays_per_s"); it != m->counters.end())
      rec.rays_per_s = it->second;
    out.push_back(rec);
    return &out.back();
  };
  for (const std::string name : {"room", "valley"}) {
    add("BM_Bake/" + name, "bake", name, "grid",
        json_params({{"spacing", compact(scene(name).scene.volume.spacing)},
                     {"samples", "1024"},
                     {"validity", "true"}}));
    for (const char* method : {"occluded", "first_hit"})
      for (int threads : {1, 2})
        add(std::string(method[0] == 'o' ? "BM_RaysOccluded/" : "BM_RaysFirstHit/") + name +
                "/threads:" + std::to_string(threads),
            "floor", name, method,
            json_params({{"rays", std::to_string(kRays)}, {"threads", std::to_string(threads)}}));
  }
  for (int cm : {100, 25})
    add("BM_PlaceGrid/" + std::to_string(cm), "placement", "room", "grid",
        json_params({{"spacing", compact(cm / 100.0)}}));
  for (const auto& [key, method] :
       {std::pair<std::string, std::string>{"BM_PlaceSpawnMerge", "spawn-merge"},
        {"BM_PlaceGradient", "gradient"}})
    if (pbr::Record* rec =
            add(key, "placement", "room", method,
                json_params({{"spacing", "1.5"},
                             {"samples", "256"},
                             {"max_iterations", method == "gradient" ? "3" : "2"},
                             {"max_probes", method == "gradient" ? "null" : "500"}}))) {
      rec->placement_ms = rec->ms;
      if (auto it = rec->counters.find("placed"); it != rec->counters.end())
        rec->probes = it->second;
    }
  for (int cm : {150, 100})
    add("BM_EdgeRays/" + std::to_string(cm), "edge_rays", "room", "edge_rays",
        json_params({{"spacing", compact(cm / 100.0)}, {"rounds", "1"}}));
  for (const pbr::SweepCase& c : pbr::sweep_cases()) {
    pbr::Record* rec = add(c.key, "sweep", "room", c.method,
                           json_params({{"spacing", compact(c.spacing)},
                                        {"spawn_contrast", c.spawn > 0 ? compact(c.spawn) : "null"},
                                        {"samples", std::to_string(pbr::kSweepSamples)},
                                        {"validity", "true"},
                                        {"edge_rays", c.edge_rays ? "true" : "false"}}));
    if (!rec) continue;
    const auto counter = [&](const char* name) -> std::optional<double> {
      auto it = rec->counters.find(name);
      return it == rec->counters.end() ? std::nullopt : std::optional<double>(it->second);
    };
    if (c.method != "grid") rec->placement_ms = counter("placement_ms");
    rec->rel_rms_error = counter("rel_rms_error");
    rec->dark_side = counter("dark_side");
    rec->lit_side = counter("lit_side");
  }
  pbr::mark_pareto_front(out);
  return out;
}

void write_outputs(const pb::Results& r, const Outputs& o) {
  const std::vector<pbr::Record> records = collect(r);
  if (g_reference_seconds >= 0) {  // the sweep ran: its table on stdout
    std::printf(
        "\nplacement sweep (room, %d samples, validity on, edge rays as named; reference %.1f "
        "s):\n",
        pbr::kSweepSamples, g_reference_seconds);
    std::printf("%-44s %7s %8s %8s %8s %10s %9s\n", "case", "probes", "rel_rms", "dark", "lit",
                "place_ms", "bake_ms");
    for (const pbr::Record& rec : records)
      if (rec.kind == "sweep")
        std::printf("%-44s %7.0f %8.3f %8.3f %8.3f %10.1f %9.1f%s\n", rec.key.c_str(),
                    rec.probes.value_or(NAN), rec.rel_rms_error.value_or(NAN),
                    rec.dark_side.value_or(NAN), rec.lit_side.value_or(NAN),
                    rec.placement_ms.value_or(NAN), rec.ms.value_or(NAN),
                    rec.pareto_front ? "  (front)" : "");
  }
  pbr::RunInfo info;
  info.cpus = static_cast<int>(std::thread::hardware_concurrency());
  double load[3];
  const int n = getloadavg(load, 3);
  info.load_avg_at_end.assign(load, load + std::max(n, 0));
  if (g_reference_seconds >= 0) info.reference_seconds = g_reference_seconds;
  if (!o.records_path.empty()) {
    if (pb::write_atomically(o.records_path, pbr::records_json(records, info)))
      std::cout << "records written to " << o.records_path << "\n";
    else
      std::cerr << "bench_probe_bake: cannot write " << o.records_path << "\n";
  }
  if (!o.chart_path.empty()) {
    if (pb::write_atomically(o.chart_path, pbr::chart(records)))
      std::cout << "chart written to " << o.chart_path << "\n";
    else
      std::cerr << "bench_probe_bake: cannot write " << o.chart_path << "\n";
    // The probe-count chart beside it: NAME.svg -> NAME_probes.svg.
    std::string probes_path = o.chart_path;
    const std::size_t dot = probes_path.rfind(".svg");
    probes_path.insert(dot == std::string::npos ? probes_path.size() : dot, "_probes");
    if (pb::write_atomically(probes_path, pbr::probes_chart(records)))
      std::cout << "chart written to " << probes_path << "\n";
    else
      std::cerr << "bench_probe_bake: cannot write " << probes_path << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  Outputs out;
  out.records_path = pb::take_flag(argc, argv, "records_out");
  out.chart_path = pb::take_flag(argc, argv, "chart_out");
  return pb::run_group(argc, argv, "probe_bake", register_benchmarks, [&](const pb::Results& r) {
    pb::Summary s = summarize(r);
    write_outputs(r, out);
    return s;
  });
}
