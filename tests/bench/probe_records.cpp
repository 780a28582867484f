// The probes group's outputs besides the summary table (probe_bench.h: write_records):
//  - --records_out: one JSON record per tetrahedralization case (ours and tetgen: points,
//    tetrahedra, ms, baseline_ms = tetgen's, speed-up; cpu_ms, baseline_cpu_ms: CPU times, ours
//    and the tetgen process's, steadier than wall time on a busy machine), per frame (method walk:
//    locate_batch, baseline no_cache; method system: probes.walk on jobs::Executor(2), baseline
//    the walk frame; entities, steps and fallbacks per entity, counted flops and bytes, ms,
//    floor_ms, goal) and per speed-versus-accuracy point (a cloud of the accuracy scene,
//    tests/probe_cloud/ probe_accuracy_scene.h: params spacing and bands, probes, ms of a
//    10,000-entity frame on 2 threads, and the interpolated irradiance's rel_rms_error and
//    max_rel_error against the reference integrator, overall and per region: interior, hull edge,
//    outside);
//  - --chart_out: the sweep's speed-versus-accuracy chart (bench_chart.h): ms (log) against
//    rel_rms_error, the best trade-off ringed (the most accurate point within the goal's time
//    for 10,000 entities; if none, the smallest ms x error).
// Both written atomically.
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
#include "probe_bench.h"

namespace penumbra::bench::probes {
namespace {
using bench_json::jnum;
using bench_json::jstr;
using bench_json::load_average;

struct Record {
  std::string key, kind, scene, method, params_json;
  int bands = 0;
  double size = 0;
  std::optional<double> ms, floor_ms, baseline_ms, goal_ms, cpu_ms, baseline_cpu_ms;
  std::optional<double> tetrahedra, baseline_tetrahedra, steps, fallbacks, flops, bytes;
  std::optional<double> probes, rel_rms, max_rel, ref_se;
  std::optional<double> region_rms[3];
};

Record measured(const Results& r, double ns_per_fma, const std::string& key) {
  Record rec;
  rec.key = key;
  rec.ms = scale(r.real_ns(key), 1e-6);
  rec.tetrahedra = r.counter(key, "tetrahedra");
  rec.steps = r.counter(key, "steps_per_entity");
  rec.fallbacks = r.counter(key, "fallbacks_per_entity");
  rec.flops = r.counter(key, "flops_per_entity");
  rec.bytes = r.counter(key, "bytes_per_entity");
  rec.probes = r.counter(key, "probes");
  rec.rel_rms = r.counter(key, "rel_rms_vs_reference");
  rec.max_rel = r.counter(key, "max_rel_vs_reference");
  rec.ref_se = r.counter(key, "reference_rel_se");
  rec.region_rms[0] = r.counter(key, "rel_rms_interior");
  rec.region_rms[1] = r.counter(key, "rel_rms_edge");
  rec.region_rms[2] = r.counter(key, "rel_rms_outside");
  if (auto f = r.counter(key, "flops_per_frame"); f && ns_per_fma > 0)
    rec.floor_ms = *f * ns_per_fma / kThreads * 1e-6;
  return rec;
}

std::vector<Record> collect(const Results& r, double ns_per_fma) {
  std::vector<Record> out;
  for (const CaseInfo& c : bench_cases()) {
    Record rec = measured(r, ns_per_fma, c.key);
    if (!rec.ms) continue;
    rec.kind = c.kind;
    rec.scene = c.scene;
    rec.method = c.method;
    rec.size = r.counter(c.key, c.kind == "frame" ? "entities" : "points").value_or(c.size);
    rec.bands = c.bands;
    rec.goal_ms = c.goal_ms;
    if (c.kind == "tetrahedralize") {
      if (c.method == "ours") {
        if (auto m = r.get(c.key)) rec.cpu_ms = m->cpu_ns * 1e-6;
      } else {
        rec.cpu_ms = r.counter(c.key, "process_cpu_ms");
      }
    }
    if (!c.baseline_key.empty()) {
      rec.baseline_ms = scale(r.real_ns(c.baseline_key), 1e-6);
      if (c.kind == "tetrahedralize") {
        rec.baseline_tetrahedra = r.counter(c.baseline_key, "tetrahedra");
        rec.baseline_cpu_ms = r.counter(c.baseline_key, "process_cpu_ms");
      }
    }
    rec.params_json = c.kind == "frame"
                          ? "{\"bands\": " + std::to_string(c.bands) +
                                ", \"threads\": " + std::to_string(kThreads) +
                                ", \"cache\": " + (c.method == "no_cache" ? "false" : "true") + "}"
                          : "{\"distribution\": " + jstr(c.scene) + "}";
    out.push_back(rec);
  }
  for (const SweepCase& c : sweep_cases()) {
    Record rec = measured(r, ns_per_fma, c.key);
    if (!rec.ms) continue;
    rec.kind = "sweep";
    rec.scene = "accuracy scene (ground, 2 boxes, lobe sky)";
    rec.method = c.cloud;
    rec.bands = c.bands;
    rec.size = kSweepEntities;
    rec.params_json = "{\"cloud\": " + jstr(c.cloud) + ", \"spacing\": " +
                      (c.spacing > 0 ? bench_json::compact(c.spacing) : "null") +
                      ", \"bands\": " + std::to_string(c.bands) +
                      ", \"windowed\": " + (c.windowed ? "true" : "false") + "}";
    rec.goal_ms = kGoalMs * kSweepEntities / kGoalEntities;
    out.push_back(rec);
  }
  return out;
}

bool on_chart(const Record& r) {
  return r.kind == "sweep" && r.ms && *r.ms > 0 && r.rel_rms;
}

// The most accurate sweep point within the goal's time; if none, the smallest ms x error.
std::string best_tradeoff(const std::vector<Record>& records) {
  std::string best;
  double best_err = 1e30, best_product = 1e30;
  for (const Record& r : records)
    if (on_chart(r) && r.goal_ms && *r.ms <= *r.goal_ms && *r.rel_rms < best_err) {
      best_err = *r.rel_rms;
      best = r.key;
    }
  if (!best.empty()) return best;
  for (const Record& r : records)
    if (on_chart(r) && *r.ms * *r.rel_rms < best_product) {
      best_product = *r.ms * *r.rel_rms;
      best = r.key;
    }
  return best;
}

std::string records_json(const std::vector<Record>& records, const std::string& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"probes\",\n  \"threads\": " << kThreads
    << ",\n  \"cpus\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(load_average())
    << ",\n  \"tetgen\": \"Debian tetgen, `tetgen -QNEF points.node` (plain Delaunay "
       "tetrahedralization, no output files), process wall time; counts from `tetgen -QNF`\""
    << ",\n  \"reference\": \"sweep: 800 query points (in the probe volume and up to 1.5 m past "
       "it, outside the boxes) x 6 axis normals, reference::environment_irradiance with 4,096 "
       "samples; rel_rms_error = sqrt(sum (E - E_ref)^2 / sum E_ref^2), max_rel_error = max |E - "
       "E_ref| / RMS(E_ref), luminance; reference_rel_se: the reference's own standard error, "
       "relative\""
    << ",\n  \"best_tradeoff_rule\": \"the sweep point with the smallest rel_rms_error within "
       "goal_ms; if none, the smallest ms x rel_rms_error\""
    << ",\n  \"best_tradeoff\": " << jstr(best) << ",\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(r.key) << ", \"kind\": " << jstr(r.kind)
      << ", \"scene\": " << jstr(r.scene) << ", \"method\": " << jstr(r.method)
      << ", \"params\": " << r.params_json << ", \"size\": " << jnum(r.size)
      << ", \"bands\": " << r.bands << ", \"ms\": " << jnum(r.ms)
      << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(quotient(r.ms, r.floor_ms))
      << ", \"baseline_ms\": " << jnum(r.baseline_ms)
      << ", \"speedup_vs_baseline\": " << jnum(quotient(r.baseline_ms, r.ms))
      << ", \"cpu_ms\": " << jnum(r.cpu_ms) << ", \"baseline_cpu_ms\": " << jnum(r.baseline_cpu_ms)
      << ", \"goal_ms\": " << jnum(r.goal_ms) << ", \"goal_met\": ";
    if (r.goal_ms && r.ms)
      o << (*r.ms <= *r.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"tetrahedra\": " << jnum(r.tetrahedra, 9)
      << ", \"baseline_tetrahedra\": " << jnum(r.baseline_tetrahedra, 9)
      << ", \"probes\": " << jnum(r.probes, 9) << ", \"steps_per_entity\": " << jnum(r.steps)
      << ", \"fallbacks_per_entity\": " << jnum(r.fallbacks)
      << ", \"flops_per_entity\": " << jnum(r.flops) << ", \"bytes_per_entity\": " << jnum(r.bytes)
      << ", \"rel_rms_error\": " << jnum(r.rel_rms) << ", \"max_rel_error\": " << jnum(r.max_rel)
      << ", \"rel_rms_error_interior\": " << jnum(r.region_rms[0])
      << ", \"rel_rms_error_edge\": " << jnum(r.region_rms[1])
      << ", \"rel_rms_error_outside\": " << jnum(r.region_rms[2])
      << ", \"reference_rel_se\": " << jnum(r.ref_se) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string chart_svg(const std::vector<Record>& records, const std::string& best) {
  std::vector<ChartPoint> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    std::string label("N");
    label += std::to_string(r.bands);
    pts.push_back({.ms = *r.ms,
                   .error_percent = *r.rel_rms * 100,
                   .series = r.method,
                   .label = label,
                   .key = r.key,
                   .front = ""});
  }
  ChartSpec spec;
  spec.title = "Probe cloud: one frame of 10,000 moving entities, walk + interpolation, 2 threads";
  spec.subtitle =
      "interpolated irradiance vs the reference integrator (800 points x 6 normals, ground + 2 "
      "boxes, lobe sky); N = SH bands";
  spec.x_label = "time of one frame (locate_batch from the cached cells), ms (log scale)";
  spec.y_label = "relative RMS irradiance error vs reference, %";
  spec.goal_ms = kGoalMs * kSweepEntities / kGoalEntities;
  spec.goal_label = "goal: 10,000 entities in 0.5 ms";
  spec.goal_label_low = true;
  spec.empty_text = "no sweep points in this run";
  spec.legend_title = "probe cloud";
  spec.best_note = "ringed: most accurate within the goal";
  spec.notes = {"grids over 8 x 8 x 4 m,", "probes in the boxes dropped"};
  if (!best.empty()) spec.ringed.push_back(best);
  return bench::chart_svg(spec, pts);
}

}  // namespace

void write_records(const Results& r, double ns_per_fma, const Outputs& out) {
  const std::vector<Record> records = collect(r, ns_per_fma);
  const std::string best = best_tradeoff(records);
  if (!out.records_path.empty()) {
    if (write_atomically(out.records_path, records_json(records, best)))
      std::cout << "records written to " << out.records_path << "\n";
    else
      std::cerr << "bench_probes: cannot write " << out.records_path << "\n";
  }
  if (!out.chart_path.empty()) {
    if (write_atomically(out.chart_path, chart_svg(records, best)))
      std::cout << "chart written to " << out.chart_path << "\n";
    else
      std::cerr << "bench_probes: cannot write " << out.chart_path << "\n";
  }
  if (!best.empty()) std::cout << "best trade-off: " << best << "\n";
}

}  // namespace penumbra::bench::probes
