// A benchmark group's speed-versus-accuracy chart as SVG, shared by the groups that write one
// (terrain: terrain_records.cpp; blockers: blocker_records.cpp): time per run on a log axis (x),
// relative RMS error in percent on a linear axis from 0 (y), one colour per series, each point
// labelled (labels placed where they overlap no point and no earlier label), the Pareto front
// of each front group dashed (no other point of the group both faster and more accurate), the
// chosen points ringed, an optional goal line, and a legend. write_atomically() writes a
// group's output through a temporary file and a rename, so a reader never sees half a file.
// line_chart_svg() draws a quantity against a small linear x range (the environment group's
// error against the number of key lights): one polyline with markers per series.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

struct ChartPoint {
  double ms = 0;             // x, > 0
  double error_percent = 0;  // y, >= 0
  std::string series;        // legend entry (colour), in order of first appearance
  std::string label;         // short text beside the point
  std::string key;           // the record's key: tooltip, and which points are ringed
  std::string front;         // Pareto front group ("": all points one group)
};

struct ChartSpec {
  std::string title, subtitle;  // plain text (escaped when written)
  std::string x_label, y_label;
  std::optional<double> goal_ms;  // a dashed red vertical line, when inside the time axis
  // The error axis ends here (percent) when some point is above it: those points are drawn
  // hollow on the top edge, their error after the label.
  std::optional<double> error_limit;
  std::string goal_label;       // its text
  bool goal_label_low = false;  // the text at the bottom of the line instead of the top
  std::string empty_text = "no points with a reference error in this run";
  std::string legend_title = "method";
  std::string front_note = "dashed grey: Pareto front";
  std::string best_note = "ringed: best trade-off";
  std::vector<std::string> notes;   // more grey lines under the legend
  std::vector<std::string> ringed;  // keys of the points to ring
};

// The chart of `points` (in drawing order) as an SVG document.
std::string chart_svg(const ChartSpec& spec, const std::vector<ChartPoint>& points);

struct LineSeries {
  std::string name;       // legend entry
  std::vector<double> x;  // the points, in drawing order; x inside [x_min, x_max]
  std::vector<double> y;  // same size as x; >= 0
  int colour = 0;         // index into the chart's 8-colour palette (taken modulo 8)
  int dash = 0;           // 0: solid, 1: dashed, 2: dotted (taken modulo 3)
};

struct LineChartSpec {
  std::string title, subtitle;  // plain text (escaped when written)
  std::string x_label, y_label;
  double x_min = 0, x_max = 1;  // the x axis, linear, a tick at each integer; x_max > x_min
  std::string legend_title = "series";
  std::vector<std::string> notes;  // grey lines under the legend
  std::string empty_text = "no points in this run";
};

// The chart of `series` (linear x from spec.x_min to x_max, linear y from 0 to a round step
// above the largest y) as an SVG document; each point a marker with a tooltip
// "name: x = X, Y". Throws std::invalid_argument naming the series whose x and y sizes differ,
// and when x_max <= x_min.
std::string line_chart_svg(const LineChartSpec& spec, const std::vector<LineSeries>& series);

// Writes `text` to `path` (creating its folder) through `path`.tmp and a rename; false on
// failure.
bool write_atomically(const std::string& path, const std::string& text);

}  // namespace penumbra::bench
