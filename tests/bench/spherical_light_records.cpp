// The spherical_lights group's outputs besides the summary table (spherical_light_bench.h):
//  - --records_out: one JSON record per frame (kind "frame": the goal frames, squirrel:14 and
//    objects:64 per blocking mode at the default min_sin; kind "sweep": objects:64 at other
//    min_sin), with the terrain group's fields (scene, method, params, size, ms, floor_ms,
//    rel_rms_error, max_rel_error) and receivers, lights, goal, counted work per receiver and
//    the reference's own noise;
//  - --chart_out: speed versus accuracy (bench_chart.h) of the objects:64 frames: ms (log)
//    against the indirect irradiance's relative RMS error against the reference integrator's
//    one-bounce estimator, one series and Pareto front per blocking mode, the fastest point of
//    each mode within kErrorBudget of the best error of that mode ringed.
// Both written atomically.
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_chart.h"
#include "bench_json.h"
#include "spherical_light_bench.h"

namespace penumbra::bench::spherical {
namespace {
using bench_json::jnum;
using bench_json::jstr;

constexpr double kThreads = 2;
constexpr double kErrorSlack = 1.1;  // ringed: fastest within 10% of the mode's best error

struct Record {
  FrameCaseInfo c;
  std::optional<double> ms, floor_ms, rel_rms, max_rel, ref_se, views, logs, exps, pairs, far, bias,
      vs_exact;
};

std::vector<Record> collect(const Results& r, double ns_per_fma) {
  std::vector<Record> out;
  for (const FrameCaseInfo& c : frame_cases()) {
    Record rec;
    rec.c = c;
    rec.ms = scale(r.real_ns(c.key), 1e-6);
    if (!rec.ms) continue;
    rec.floor_ms = frame_floor_ms(r, c.key, ns_per_fma);
    rec.rel_rms = r.counter(c.key, "rel_rms_vs_reference");
    rec.max_rel = r.counter(c.key, "max_rel_vs_reference");
    rec.ref_se = r.counter(c.key, "reference_rel_std_error");
    rec.views = r.counter(c.key, "views_per_receiver");
    rec.logs = r.counter(c.key, "logs_per_receiver");
    rec.exps = r.counter(c.key, "exponentials_per_receiver");
    rec.pairs = r.counter(c.key, "pairs_per_receiver");
    rec.far = r.counter(c.key, "far_per_receiver");
    rec.bias = r.counter(c.key, "sum_vs_reference");
    rec.vs_exact = r.counter(c.key, "rel_rms_vs_per_receiver");
    out.push_back(rec);
  }
  return out;
}

bool on_chart(const Record& r) {
  return r.c.scene == "objects:64" && r.ms && *r.ms > 0 && r.rel_rms;
}

std::map<std::string, std::string> best_tradeoffs(const std::vector<Record>& records) {
  std::map<std::string, double> best_error;
  for (const Record& r : records)
    if (on_chart(r) &&
        (!best_error.contains(r.c.blocking) || *r.rel_rms < best_error[r.c.blocking]))
      best_error[r.c.blocking] = *r.rel_rms;
  std::map<std::string, std::string> best;
  std::map<std::string, double> best_ms;
  for (const Record& r : records) {
    if (!on_chart(r) || *r.rel_rms > kErrorSlack * best_error[r.c.blocking]) continue;
    if (best_ms.contains(r.c.blocking) && *r.ms >= best_ms[r.c.blocking]) continue;
    best_ms[r.c.blocking] = *r.ms;
    best[r.c.blocking] = r.c.key;
  }
  return best;
}

std::string records_json(const std::vector<Record>& records,
                         const std::map<std::string, std::string>& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"spherical_lights\",\n  \"threads\": " << kThreads
    << ",\n  \"cpus\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(bench_json::load_average()) << ",\n  \"bands\": 4"
    << ",\n  \"sky\": \"radiance 0.4 + 1.6 max(0, z)^2, tinted; 4-band SH for ours, the 64 x 32 "
       "map for the reference\""
    << ",\n  \"error_reference\": \"reference::indirect_irradiance (one diffuse bounce off the "
       "boxes' meshes with their albedo, 512 directions, 8 direct samples per hit) at every "
       "100th (objects:64) or 21st (squirrel:14) receiver; rel_rms_error = sqrt(sum |E - "
       "E_ref|^2 / sum |E_ref|^2), max_rel_error = max |E - E_ref| / RMS(E_ref), RGB; "
       "reference_rel_std_error: the reference's own noise on the same scale; sum_vs_reference: "
       "sum E / "
       "sum E_ref (the bias); rel_rms_vs_per_receiver (clusters): against irradiance() at every "
       "receiver, the clusters' own error\""
    << ",\n  \"best_tradeoff_rule\": \"per blocking mode (objects:64), the fastest frame whose "
       "rel_rms_error is within 10% of the mode's smallest\""
    << ",\n  \"best_tradeoff\": {";
  bool first = true;
  for (const auto& [mode, key] : best) {
    o << (first ? "" : ", ") << jstr(mode) << ": " << jstr(key);
    first = false;
  }
  o << "},\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(r.c.key)
      << ", \"kind\": " << jstr(r.c.kind) << ", \"scene\": " << jstr(r.c.scene)
      << ", \"method\": " << jstr(r.c.blocking + " " + r.c.method)
      << ", \"params\": {\"bands\": 4, \"min_sin\": " << bench_json::compact(r.c.min_sin)
      << ", \"blocking\": " << jstr(r.c.blocking)
      << ", \"clusters\": " << (r.c.method == "clusters" ? "true" : "false")
      << ", \"far_ratio\": " << bench_json::compact(r.c.far_ratio) << "}"
      << ", \"size\": " << jnum(r.c.receivers) << ", \"receivers\": " << jnum(r.c.receivers)
      << ", \"lights\": " << jnum(r.c.lights) << ", \"ms\": " << jnum(r.ms)
      << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(quotient(r.ms, r.floor_ms))
      << ", \"goal_ms\": " << jnum(r.c.goal_ms) << ", \"goal_met\": ";
    if (r.c.goal_ms && r.ms)
      o << (*r.ms <= *r.c.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"views_per_receiver\": " << jnum(r.views)
      << ", \"pairs_per_receiver\": " << jnum(r.pairs)
      << ", \"logs_per_receiver\": " << jnum(r.logs)
      << ", \"exponentials_per_receiver\": " << jnum(r.exps)
      << ", \"far_per_receiver\": " << jnum(r.far) << ", \"rel_rms_error\": " << jnum(r.rel_rms)
      << ", \"max_rel_error\": " << jnum(r.max_rel)
      << ", \"reference_rel_std_error\": " << jnum(r.ref_se)
      << ", \"sum_vs_reference\": " << jnum(r.bias)
      << ", \"rel_rms_vs_per_receiver\": " << jnum(r.vs_exact) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string chart(const std::vector<Record>& records,
                  const std::map<std::string, std::string>& best) {
  std::vector<ChartPoint> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    std::string label("s");  // not "s" + ...: GCC 12's -Wrestrict false positive
    label += bench_json::compact(r.c.min_sin);
    if (r.c.method == "clusters") label += " f" + bench_json::compact(r.c.far_ratio);
    std::string series(r.c.blocking == "per_sphere" ? "per sphere" : "per object");
    series += r.c.method == "clusters" ? ", clusters" : ", per receiver";
    pts.push_back({.ms = *r.ms,
                   .error_percent = *r.rel_rms * 100,
                   .series = series,
                   .label = label,
                   .key = r.c.key,
                   .front = r.c.blocking});
  }
  ChartSpec spec;
  spec.title = "Spherical lights: one frame, 100,000 receivers, 64 SLs (8 objects), 2 threads";
  spec.subtitle = "indirect irradiance error vs the reference integrator's one bounce; s = min_sin";
  spec.x_label = "time of one frame (set_lights + shade), ms (log scale)";
  spec.y_label = "relative RMS indirect irradiance error vs reference, %";
  spec.goal_ms = 30;
  spec.goal_label = "goal 30 ms";
  spec.goal_label_low = true;
  spec.empty_text = "no frames with a reference error in this run";
  spec.legend_title = "blocking";
  spec.front_note = "dashed grey: Pareto front per mode";
  spec.best_note = "ringed: fastest within 10% of the mode's best error";
  spec.error_limit = 100;
  for (const auto& [mode, key] : best) spec.ringed.push_back(key);
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
      std::cerr << "bench_spherical_lights: cannot write " << out.records_path << "\n";
  }
  if (!out.chart_path.empty()) {
    if (write_atomically(out.chart_path, chart(records, best)))
      std::cout << "chart written to " << out.chart_path << "\n";
    else
      std::cerr << "bench_spherical_lights: cannot write " << out.chart_path << "\n";
  }
  for (const auto& [mode, key] : best)
    std::cout << "best trade-off " << mode << ": " << key << "\n";
}

}  // namespace penumbra::bench::spherical
