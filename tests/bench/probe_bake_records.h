// The probe_bake group's records and chart (probe_bake_bench.cpp measures, this writes;
// docs/probe_bake.md, "Benchmarks"): the placement sweep's cases, one JSON record per case
// (--records_out) and the speed-versus-accuracy chart (--chart_out, bench_chart.h). Pure
// functions of the measured values, without Google Benchmark (tested by
// probe_bake_records_test.cpp).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench_chart.h"

namespace penumbra::bench::probe_bake {

// One point of the placement sweep in the room ([Sukys14] sec. 3.1; the cases of the test
// RoomAccuracy.ErrorVersusProbeCount): a uniform grid, spawn and merge from a start grid at a
// spawn threshold, or gradient ascent from a start grid.
struct SweepCase {
  std::string key;         // Google Benchmark name, "BM_PlacementSweep/..."
  std::string method;      // "grid", "spawn-merge", "gradient"
  float spacing = 0;       // grid spacing or the adaptive methods' start grid, m
  float spawn = 0;         // spawn-merge's spawn contrast threshold (0: not spawn-merge)
  bool edge_rays = false;  // edge rays after the placement ([Sukys14] sec. 3.2.2, default rounds)
};

// Bake settings of every sweep point (as the accuracy test): 512 samples, validity on, edge
// rays off; spawn-merge's other settings and its probe cap the defaults (4,000).
inline constexpr int kSweepSamples = 512;
// Repetitions of each sweep point's bake (its time: the median).
inline constexpr int kSweepRepetitions = 3;

// grid 2, 1.5, 1, 0.75 m; spawn-merge from 2 m (spawn 0.7, 0.5) and 1 m (0.9, 0.7); gradient
// from 1.5, 1, 0.75 m; with edge rays after it ("METHOD + edge rays"): grid 1.5 m, spawn-merge
// from 2 m (0.7), gradient from 1.5 and 1 m (the leaky ones).
const std::vector<SweepCase>& sweep_cases();

// One record: a Google Benchmark case of the group or a sweep point.
struct Record {
  std::string key, kind;  // kind: bake, floor, placement, edge_rays, sweep
  std::string scene, method;
  std::string params_json = "{}";      // a JSON object
  std::optional<double> probes;        // probes in the cloud (or points placed)
  std::optional<double> ms;            // wall time of one run (median of the repetitions)
  std::optional<double> placement_ms;  // adaptive placement alone (its captures included)
  std::optional<double> rays_per_s;
  std::optional<double> rel_rms_error;  // sweep: free-space points
  std::optional<double> dark_side;      // sweep: the leak metric (dark side of the inner wall)
  std::optional<double> lit_side;
  bool pareto_front = false;               // sweep: no other sweep point faster and more accurate
  std::map<std::string, double> counters;  // every counter Google Benchmark reported
};

// What the records file says about the run.
struct RunInfo {
  int cpus = 0;
  std::vector<double> load_avg_at_end;      // 1, 5, 15 minutes, as `uptime` prints them
  std::optional<double> reference_seconds;  // the sweep's reference values, computed once
};

// Marks the sweep records on the Pareto front of (ms, rel_rms_error): no other sweep record with
// both is at most as slow and at most as wrong, and better in one.
void mark_pareto_front(std::vector<Record>& records);

// The sweep point of the room's default placement (grid at its 1 m spacing), ringed on the chart.
inline constexpr const char* kDefaultKey = "BM_PlacementSweep/grid_1m";

// The records file (JSON).
std::string records_json(const std::vector<Record>& records, const RunInfo& info);

// The chart's points: the sweep records with a time and an error, one series per method,
// labelled with the probe count; and the chart (bake time, log, against rel. RMS error).
std::vector<ChartPoint> chart_points(const std::vector<Record>& records);
std::string chart(const std::vector<Record>& records);
// The chart: probe count (log) against rel. RMS error, one series per method (the same
// points, x the probes instead of the time); written beside the first as NAME_probes.svg.
std::string probes_chart(const std::vector<Record>& records);

}  // namespace penumbra::bench::probe_bake
