// The probe_bake group's records and chart (probe_bake_records.h).
#include "probe_bake_records.h"

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "bench_json.h"

namespace penumbra::bench::probe_bake {
namespace {

using bench_json::compact;
using bench_json::jnum;
using bench_json::jstr;

bool on_chart(const Record& r) {
  return r.kind == "sweep" && r.ms && *r.ms > 0 && r.rel_rms_error &&
         std::isfinite(*r.rel_rms_error);
}

std::string spacing_text(float spacing) {
  return compact(spacing) + " m";
}

}  // namespace

const std::vector<SweepCase>& sweep_cases() {
  static const std::vector<SweepCase> cases = [] {
    std::vector<SweepCase> out;
    for (float s : {2.0f, 1.5f, 1.0f, 0.75f})
      out.push_back({"BM_PlacementSweep/grid_" + compact(s) + "m", "grid", s, 0});
    for (const auto& [start, spawn] : {std::pair{2.0f, 0.7f}, std::pair{2.0f, 0.5f},
                                       std::pair{1.0f, 0.9f}, std::pair{1.0f, 0.7f}})
      out.push_back(
          {"BM_PlacementSweep/spawn_merge_" + compact(start) + "m/spawn:" + compact(spawn),
           "spawn-merge", start, spawn});
    for (float s : {1.5f, 1.0f, 0.75f})
      out.push_back({"BM_PlacementSweep/gradient_" + compact(s) + "m", "gradient", s, 0});
    // Adaptive placement combined with edge rays (and the grid with them, for comparison).
    out.push_back({"BM_PlacementSweep/grid_1.5m/edge_rays", "grid + edge rays", 1.5f, 0, true});
    out.push_back({"BM_PlacementSweep/spawn_merge_2m/spawn:0.7/edge_rays",
                   "spawn-merge + edge rays", 2.0f, 0.7f, true});
    for (float s : {1.5f, 1.0f})
      out.push_back({"BM_PlacementSweep/gradient_" + compact(s) + "m/edge_rays",
                     "gradient + edge rays", s, 0, true});
    return out;
  }();
  return cases;
}

void mark_pareto_front(std::vector<Record>& records) {
  for (Record& r : records) {
    r.pareto_front = false;
    if (!on_chart(r)) continue;
    bool dominated = false;
    for (const Record& o : records) {
      if (&o == &r || !on_chart(o)) continue;
      const bool no_worse = *o.ms <= *r.ms && *o.rel_rms_error <= *r.rel_rms_error;
      const bool better = *o.ms < *r.ms || *o.rel_rms_error < *r.rel_rms_error;
      dominated = dominated || (no_worse && better);
    }
    r.pareto_front = !dominated;
  }
}

std::string records_json(const std::vector<Record>& records, const RunInfo& info) {
  std::ostringstream o;
  o << "{\n  \"group\": \"probe_bake\",\n  \"cpus\": " << info.cpus
    << ",\n  \"load_avg_at_end\": [";
  for (std::size_t i = 0; i < info.load_avg_at_end.size(); ++i)
    o << (i ? ", " : "") << jnum(info.load_avg_at_end[i], 3);
  o << "]"
    << ",\n  \"sweep_repetitions\": " << kSweepRepetitions
    << ",\n  \"reference_seconds\": " << jnum(info.reference_seconds, 4)
    << ",\n  \"sweep\": \"room (scenes/room.json); each point baked with " << kSweepSamples
    << " samples, validity on, edge rays only in the \"+ edge rays\" methods, the ray tracer built "
       "once (bake_probe_cloud with a "
       "reference::Scene); ms: the bake's wall time, placement_ms: the adaptive placement in it "
       "(its captures included)\""
    << ",\n  \"reference\": \"the accuracy tests' points "
       "(tests/probe_bake/room_accuracy_points.h): "
       "120 free-space points (0.1 m clear of every solid), 60 on the inner wall's dark side "
       "(x in [0.25, 1] m, y < 1.5 m), 60 on its lit side; 6 axis normals each; reference "
       "environment (256 samples) + lights (256) + one bounce (1,024), computed once per run; "
       "rel_rms_error = sqrt(sum (E - E_ref)^2 / sum E_ref^2) over the free points, normals and "
       "RGB; dark_side, lit_side: the same over those sets (dark_side: the leak metric)\""
    << ",\n  \"pareto_rule\": \"no other sweep point with ms and rel_rms_error both no larger, "
       "one smaller\""
    << ",\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(r.key) << ", \"kind\": " << jstr(r.kind)
      << ", \"scene\": " << jstr(r.scene) << ", \"method\": " << jstr(r.method)
      << ", \"params\": " << r.params_json << ", \"probes\": " << jnum(r.probes, 9)
      << ", \"ms\": " << jnum(r.ms) << ", \"placement_ms\": " << jnum(r.placement_ms)
      << ", \"rays_per_s\": " << jnum(r.rays_per_s)
      << ", \"rel_rms_error\": " << jnum(r.rel_rms_error)
      << ", \"dark_side\": " << jnum(r.dark_side) << ", \"lit_side\": " << jnum(r.lit_side)
      << ", \"pareto_front\": " << (r.pareto_front ? "true" : "false") << ", \"counters\": {";
    bool first = true;
    for (const auto& [name, value] : r.counters) {
      o << (first ? "" : ", ") << jstr(name) << ": " << jnum(value, 9);
      first = false;
    }
    o << "}}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::vector<ChartPoint> chart_points(const std::vector<Record>& records) {
  std::vector<ChartPoint> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    std::string label;
    for (const SweepCase& c : sweep_cases())
      if (c.key == r.key) {
        label = spacing_text(c.spacing);
        if (c.spawn > 0) label.append("/").append(compact(c.spawn));
      }
    if (r.probes) label.append(label.empty() ? "" : ", ").append(compact(*r.probes));
    pts.push_back({.ms = *r.ms,
                   .error_percent = *r.rel_rms_error * 100,
                   .series = r.method,
                   .label = label,
                   .key = r.key,
                   .front = ""});
  }
  return pts;
}

namespace {
// What both charts share: the sweep's error axis, legend, notes and the default ringed.
ChartSpec sweep_spec(std::string title, std::string x_label) {
  ChartSpec spec;
  spec.title = std::move(title);
  spec.subtitle =
      "interpolated irradiance vs the reference integrator (120 free-space points x 6 normals); "
      "512 samples, validity on, edge rays as named";
  spec.x_label = std::move(x_label);
  spec.y_label = "relative RMS irradiance error vs reference, %";
  spec.empty_text = "no sweep points in this run";
  spec.legend_title = "placement";
  spec.best_note = "ringed: the room's default (grid 1 m)";
  spec.notes = {"labels: start spacing[/spawn", "threshold], probes"};
  spec.ringed.emplace_back(kDefaultKey);  // not push_back(string): gcc 12 + PCH warn
  return spec;
}
}  // namespace

std::string chart(const std::vector<Record>& records) {
  return chart_svg(
      sweep_spec("Probe bake, room: placement methods, bake time against accuracy",
                 "bake wall time (placement + capture + validity + tetrahedralization), ms (log)"),
      chart_points(records));
}

std::string probes_chart(const std::vector<Record>& records) {
  std::vector<ChartPoint> pts;
  for (ChartPoint p : chart_points(records)) {
    for (const Record& r : records)
      if (r.key == p.key && r.probes) p.ms = *r.probes;  // x: probes
    pts.push_back(std::move(p));
  }
  ChartSpec spec = sweep_spec("Probe bake, room: error against probe count per placement method",
                              "probes in the cloud (log)");
  spec.front_note = "dashed grey: fewest probes for the error";
  return chart_svg(spec, pts);
}

}  // namespace penumbra::bench::probe_bake
