// The terrain group's outputs besides the summary table: one JSON record per measured case
// and per speed-versus-accuracy point (--records_out; scene, method, params, size, ms, floor_ms,
// rel_rms_error, max_rel_error, ...), and the speed-versus-accuracy chart as SVG (--chart_out),
// both written atomically (temporary file, then rename; the chart writer and the write are
// shared with the blockers group: bench_chart.h). summarize() (terrain_summary.cpp)
// builds the records from a run's results and writes both.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {

// One measured case or sweep point.
struct Record {
  const CaseInfo* info;
  std::optional<double> ms, floor_ms, baseline_ms;
  tbr::ErrorSummary error;
};

// Where --records_out and --chart_out write ("": not written).
struct Outputs {
  std::string records_path, chart_path;
};

// The group's summary rows from a run's results; writes the records and the chart to `out`.
pb::Summary summarize(const pb::Results& r, const Outputs& out);

// Points of the chart: the sweep points and the brute-force case, with an error.
bool on_chart(const Record& r);

// The records file; `best`: the best trade-off's key (summarize()).
std::string records_json(const std::vector<Record>& records, const std::string& best);
// The chart; the point `best_key` is ringed.
std::string chart_svg(const std::vector<Record>& records, const std::string& best_key);

}  // namespace penumbra::terrain_bench
