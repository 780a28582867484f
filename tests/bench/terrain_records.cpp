// The terrain group's records (JSON) and speed-versus-accuracy chart (SVG): terrain_records.h.
#include "terrain_records.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "bench_chart.h"
#include "bench_json.h"

namespace penumbra::terrain_bench {
namespace {
using bench_json::jnum;
using bench_json::jstr;
using bench_json::load_average;

// Series of the chart: one colour per method and varied parameter.
std::string series_of(const CaseInfo& c) {
  if (c.env.method == "march") {
    if (c.env.n_phi != 32) return "march ls 4 lo 2, n_phi";
    return "march lo " + std::to_string(static_cast<int>(c.env.lo)) + ", ls (n_phi 32)";
  }
  if (c.env.method == "sweep") return c.env.bands != 4 ? "sweep, bands 3 and 5" : "sweep, n_phi";
  return "brute force (n_phi 32)";
}
// A point's label: its varied parameter ("ls3", "n16", "N5 n8", "bf").
std::string label_of(const CaseInfo& c) {
  const auto tagged = [](const char* tag, int value) {
    std::string s(tag);  // not tag + std::to_string(): GCC 12's -Wrestrict false positive
    s += std::to_string(value);
    return s;
  };
  if (c.env.method == "march" && c.env.n_phi == 32) return tagged("ls", c.env.ls);
  if (c.env.bands != 4)
    return tagged("N", c.env.bands) + (c.env.n_phi != 32 ? tagged(" n", c.env.n_phi) : "");
  if (c.env.method == "brute_force") return "bf";
  return tagged("n", c.env.n_phi);
}

}  // namespace

bool on_chart(const Record& r) {
  const CaseInfo& c = *r.info;
  return c.is_env && c.size == kSize && r.ms && r.error.rel_rms &&
         (c.kind == "sweep" || c.method == "brute_force");
}

std::string records_json(const std::vector<Record>& records, const std::string& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"terrain\",\n  \"scene\": " << jstr(tbr::kSceneName)
    << ",\n  \"environment\": " << jstr(tbr::environment_name())
    << ",\n  \"reference\": " << jstr(tbr::reference_description())
    << ",\n  \"threads\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(load_average())
    << ",\n  \"best_tradeoff_rule\": \"most accurate chart point within 10 ms; if none, smallest "
       "ms x rel_rms\""
    << ",\n  \"best_tradeoff\": " << jstr(best) << ",\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    const CaseInfo& c = *r.info;
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(c.key) << ", \"kind\": " << jstr(c.kind)
      << ", \"scene\": " << jstr(tbr::kSceneName) << ", \"method\": " << jstr(c.method)
      << ", \"params\": " << c.params_json << ", \"size\": " << c.size << ", \"ms\": " << jnum(r.ms)
      << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(pb::quotient(r.ms, r.floor_ms))
      << ", \"goal_ms\": " << jnum(c.goal_ms) << ", \"goal_met\": ";
    if (c.goal_ms && r.ms)
      o << (*r.ms <= *c.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"rel_rms_error\": " << jnum(r.error.rel_rms)
      << ", \"max_rel_error\": " << jnum(r.error.max_rel)
      << ", \"reference_rel_se\": " << jnum(r.error.ref_rel_se) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string chart_svg(const std::vector<Record>& records, const std::string& best_key) {
  std::vector<pb::ChartPoint> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    pts.push_back({.ms = *r.ms,
                   .error_percent = *r.error.rel_rms * 100,
                   .series = series_of(*r.info),
                   .label = label_of(*r.info),
                   .key = r.info->key,
                   .front = ""});
  }
  pb::ChartSpec spec;
  spec.title = "Terrain shadows: full environment update, " + std::to_string(kSize) + "x" +
               std::to_string(kSize) + " " + tbr::kSceneName + ", 2 threads";
  spec.subtitle = "irradiance error vs Monte Carlo reference (" + tbr::environment_name() +
                  "); n = n_phi, ls = level step, N = SH bands";
  spec.x_label = "time of the full environment update, ms (log scale)";
  spec.y_label = "relative RMS irradiance error, %";
  spec.goal_ms = 10;
  spec.goal_label = "goal 10 ms";
  spec.notes = {"n_phi 32 unless labelled nK", "march: pyramid build included"};
  spec.ringed = {best_key};
  return pb::chart_svg(spec, pts);
}

}  // namespace penumbra::terrain_bench
