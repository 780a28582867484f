// The blockers group's outputs besides the summary table (blocker_bench.h: write_records):
//  - --records_out: one JSON record per frame case (blocker_frame_bench.cpp; 99,856 receivers,
//    4 bands) and per speed-versus-accuracy point (blocker_sweep_bench.cpp; 24,964 receivers,
//    3-5 bands): scene, method, params (bands, min_sin, far_error, hierarchy), receivers,
//    blockers, bands, ms (median), floor_ms, baseline_ms (all pairs, same scene, receivers and
//    bands), view_blocker calls and log-SH additions per receiver, mean HYB squarings, and the
//    irradiance's rel_rms_error and max_rel_error against all pairs;
//  - --chart_out: the sweep's speed-versus-accuracy chart (bench_chart.h): ms (log) against
//    rel_rms_error, one Pareto front per scene, the best trade-off of each scene ringed: the
//    fastest point within the error budget (kErrorBudget) against all pairs both at its bands
//    and at 5 bands (so a 3-band point pays for its band limit), or, when none is, the smallest
//    ms x error.
// Both written atomically (temporary file, then rename).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_chart.h"
#include "bench_json.h"
#include "blocker_bench.h"
#include "penumbra/systems/blocker_accumulation/receiver_clusters.h"

namespace penumbra::bench::blockers {
namespace {
using bench_json::jnum;
using bench_json::jstr;
using bench_json::load_average;

constexpr double kGoalReceivers = 100'000;  // the goal's receivers
constexpr double kErrorBudget = 0.02;       // best trade-off: rel RMS vs all pairs at most 2%
constexpr double kErrorLimit = 20;          // the chart's error axis, percent

struct Record {
  std::string key, kind, scene, method, params_json;
  int bands = 4;
  double receivers = 0, blockers = 0;
  std::optional<double> ms, floor_ms, baseline_ms, goal_ms;
  std::optional<double> views, adds, squares, rel_rms, max_rel, rel_rms_5;
  float min_sin = 0, far_error = 0;
};

// A record's params: bands, min_sin (0 for all pairs), hierarchy, far_error (clusters).
std::string params_json(const std::string& method, int bands, float min_sin, float far_error) {
  std::string p = "{\"bands\": " + std::to_string(bands) +
                  ", \"min_sin\": " + bench_json::compact(method == "all_pairs" ? 0.0 : min_sin) +
                  ", \"hierarchy\": " +
                  (method == "hierarchy" || method == "clusters" ? "\"objects\"" : "\"off\"");
  if (method == "clusters") p += ", \"far_error\": " + bench_json::compact(far_error);
  return p + "}";
}

Record measured(const Results& r, double ns_per_fma, const std::string& key) {
  Record rec;
  rec.key = key;
  rec.ms = scale(r.real_ns(key), 1e-6);
  rec.receivers = r.counter(key, "receivers").value_or(0);
  rec.views = r.counter(key, "views_per_receiver");
  rec.adds = r.counter(key, "added_per_receiver");
  rec.squares = r.counter(key, "squares_mean");
  rec.rel_rms = r.counter(key, "rel_rms_vs_all_pairs");
  rec.max_rel = r.counter(key, "max_rel_vs_all_pairs");
  rec.rel_rms_5 = r.counter(key, "rel_rms_vs_all_pairs_5_bands");
  if (auto flops = r.counter(key, "flops_per_frame"); flops && ns_per_fma > 0)
    rec.floor_ms = *flops * ns_per_fma / kThreads * 1e-6;
  return rec;
}

std::vector<Record> collect(const Results& r, double ns_per_fma) {
  std::vector<Record> out;
  const ba::SphereBlockerSettings defaults;
  std::map<std::string, std::string> all_pairs_frame;  // scene -> key
  for (const FrameCaseInfo& c : frame_cases())
    if (c.method == "all_pairs") all_pairs_frame[c.scene] = c.key;
  for (const FrameCaseInfo& c : frame_cases()) {
    Record rec = measured(r, ns_per_fma, c.key);
    if (!rec.ms) continue;
    rec.kind = "frame";
    rec.scene = c.scene;
    rec.method = c.method;
    rec.bands = 4;
    rec.min_sin = c.method == "all_pairs" ? 0.0f : defaults.min_sin;
    rec.far_error = ba::ReceiverClusterSettings{}.far_error;
    rec.params_json = params_json(c.method, 4, rec.min_sin, rec.far_error);
    rec.blockers = static_cast<double>(frame_scene(c.scene).spheres.size());
    rec.baseline_ms = scale(r.real_ns(all_pairs_frame[c.scene]), 1e-6);
    if (rec.blockers == 400) rec.goal_ms = kGoalMs;
    if (c.method == "all_pairs") rec.rel_rms = rec.max_rel = 0.0;
    out.push_back(rec);
  }
  std::map<std::string, std::string> all_pairs_sweep;  // scene + bands -> key
  for (const SweepPoint& p : sweep_points())
    if (p.method == "all_pairs") all_pairs_sweep[p.scene + std::to_string(p.bands)] = p.key;
  for (const SweepPoint& p : sweep_points()) {
    Record rec = measured(r, ns_per_fma, p.key);
    if (!rec.ms) continue;
    rec.kind = "sweep";
    rec.scene = p.scene;
    rec.method = p.method;
    rec.bands = p.bands;
    rec.min_sin = p.min_sin;
    rec.far_error = p.far_error;
    rec.params_json = params_json(p.method, p.bands, p.min_sin, p.far_error);
    rec.blockers = r.counter(p.key, "blockers").value_or(0);
    rec.baseline_ms = scale(r.real_ns(all_pairs_sweep[p.scene + std::to_string(p.bands)]), 1e-6);
    out.push_back(rec);
  }
  return out;
}

bool on_chart(const Record& r) {
  return r.kind == "sweep" && r.ms && *r.ms > 0 && r.rel_rms;
}

// Per scene: the fastest chart point within the error budget; if none, the smallest ms x error.
std::map<std::string, std::string> best_tradeoffs(const std::vector<Record>& records) {
  std::map<std::string, std::string> best;
  std::map<std::string, double> best_ms, best_product;
  for (const Record& r : records) {
    if (!on_chart(r) || *r.rel_rms > kErrorBudget || r.rel_rms_5.value_or(1) > kErrorBudget)
      continue;
    if (best_ms.contains(r.scene) && *r.ms >= best_ms[r.scene]) continue;
    best_ms[r.scene] = *r.ms;
    best[r.scene] = r.key;
  }
  for (const Record& r : records) {
    if (!on_chart(r) || best_ms.contains(r.scene)) continue;
    const double product = *r.ms * std::max(*r.rel_rms, 1e-9);
    if (best_product.contains(r.scene) && product >= best_product[r.scene]) continue;
    best_product[r.scene] = product;
    best[r.scene] = r.key;
  }
  return best;
}

std::string records_json(const std::vector<Record>& records,
                         const std::map<std::string, std::string>& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"blockers\",\n  \"threads\": " << kThreads
    << ",\n  \"cpus\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(load_average())
    << ",\n  \"sky\": \"uniform radiance 1, kProduct shading, upward receivers\""
    << ",\n  \"error_reference\": \"all_pairs (min_sin 0, hierarchy off) at the same scene, "
       "receivers and bands; rel_rms_error = sqrt(sum (E - E_all)^2 / sum E_all^2), "
       "max_rel_error = max |E - E_all| / RMS(E_all); frames at every 50th receiver, sweep at "
       "every receiver; rel_rms_error_vs_5_bands (sweep): against all pairs at 5 bands, the band "
       "limit's share included\""
    << ",\n  \"error_budget\": " << jnum(kErrorBudget)
    << ",\n  \"best_tradeoff_rule\": \"per scene, the fastest sweep point with rel_rms_error and "
       "rel_rms_error_vs_5_bands both <= error_budget; if none, the smallest ms x rel_rms_error\""
    << ",\n  \"best_tradeoff\": {";
  bool first = true;
  for (const auto& [scene, key] : best) {
    o << (first ? "" : ", ") << jstr(scene) << ": " << jstr(key);
    first = false;
  }
  o << "},\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(r.key) << ", \"kind\": " << jstr(r.kind)
      << ", \"scene\": " << jstr(r.scene) << ", \"method\": " << jstr(r.method)
      << ", \"params\": " << r.params_json << ", \"receivers\": " << jnum(r.receivers)
      << ", \"blockers\": " << jnum(r.blockers) << ", \"bands\": " << r.bands
      << ", \"ms\": " << jnum(r.ms) << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(quotient(r.ms, r.floor_ms))
      << ", \"baseline_ms\": " << jnum(r.baseline_ms)
      << ", \"speedup_vs_all_pairs\": " << jnum(quotient(r.baseline_ms, r.ms))
      << ", \"goal_ms\": " << jnum(r.goal_ms) << ", \"goal_met\": ";
    if (r.goal_ms && r.ms)
      o << (*r.ms <= *r.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"views_per_receiver\": " << jnum(r.views)
      << ", \"adds_per_receiver\": " << jnum(r.adds) << ", \"squares_mean\": " << jnum(r.squares)
      << ", \"rel_rms_error\": " << jnum(r.rel_rms) << ", \"max_rel_error\": " << jnum(r.max_rel)
      << ", \"rel_rms_error_vs_5_bands\": " << jnum(r.rel_rms_5) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string chart_svg(const std::vector<Record>& records,
                      const std::map<std::string, std::string>& best) {
  std::vector<ChartPoint> pts;
  double receivers = 0;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    receivers = r.receivers;
    std::string label("N");  // not "N" + std::to_string(): GCC 12's -Wrestrict false positive
    label += std::to_string(r.bands);
    if (r.method == "clusters" && r.far_error != ba::ReceiverClusterSettings{}.far_error)
      label += " e" + bench_json::compact(r.far_error);
    else if (r.method != "all_pairs")
      label += " s" + bench_json::compact(r.min_sin);
    pts.push_back({.ms = *r.ms,
                   .error_percent = *r.rel_rms * 100,
                   .series = r.scene + " " + (r.method == "all_pairs" ? "all pairs" : r.method),
                   .label = label,
                   .key = r.key,
                   .front = r.scene});
  }
  ChartSpec spec;
  char receivers_text[32];
  std::snprintf(receivers_text, sizeof receivers_text, "%.0f", receivers);
  spec.title = std::string("Blocker accumulation: one frame, ") + receivers_text +
               " upward receivers, 400 spheres, 2 threads";
  spec.subtitle =
      "irradiance error vs all pairs at the same bands (every receiver); N = SH bands, "
      "s = min_sin, e = far_error";
  spec.x_label = "time of one frame (set_blockers + shade), ms (log scale)";
  spec.y_label = "relative RMS irradiance difference vs all pairs, %";
  if (receivers > 0) {
    spec.goal_ms = kGoalMs * receivers / kGoalReceivers;
    char goal[96];
    std::snprintf(goal, sizeof goal, "goal 30 ms per 100k receivers: %.1f ms", *spec.goal_ms);
    spec.goal_label = goal;
    spec.goal_label_low = true;
  }
  spec.empty_text = "no sweep points in this run";
  spec.legend_title = "scene, method";
  spec.front_note = "dashed grey: Pareto front per scene";
  spec.best_note = "ringed: fastest within " + bench_json::compact(100 * kErrorBudget) + "% error";
  spec.notes = {"(vs all pairs: same and 5 bands)", "clusters: far_error 0.005,",
                "e: far_error at min_sin 0.05", "all pairs: 0 by definition",
                "hollow on top: error above " + bench_json::compact(kErrorLimit) + "%"};
  spec.error_limit = kErrorLimit;
  for (const auto& [scene, key] : best) spec.ringed.push_back(key);
  return bench::chart_svg(spec, pts);
}

}  // namespace

void write_records(const Results& r, double ns_per_fma, const Outputs& out) {
  const std::vector<Record> records = collect(r, ns_per_fma);
  const std::map<std::string, std::string> best = best_tradeoffs(records);
  if (!out.records_path.empty()) {
    if (write_atomically(out.records_path, records_json(records, best)))
      std::cout << "records written to " << out.records_path << "\n";
    else
      std::cerr << "bench_blockers: cannot write " << out.records_path << "\n";
  }
  if (!out.chart_path.empty()) {
    if (write_atomically(out.chart_path, chart_svg(records, best)))
      std::cout << "chart written to " << out.chart_path << "\n";
    else
      std::cerr << "bench_blockers: cannot write " << out.chart_path << "\n";
  }
  for (const auto& [scene, key] : best)
    std::cout << "best trade-off " << scene << ": " << key << "\n";
}

}  // namespace penumbra::bench::blockers
