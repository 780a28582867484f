// The shared speed-versus-accuracy chart writer and atomic write (bench_chart.h).
#include "bench_chart.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace pb = penumbra::bench;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

pb::ChartSpec spec() {
  pb::ChartSpec s;
  s.title = "title <a & b>";
  s.subtitle = "subtitle";
  s.x_label = "ms";
  s.y_label = "error, %";
  return s;
}

TEST(BenchChart, EmptyChartSaysSo) {
  pb::ChartSpec s = spec();
  s.empty_text = "nothing here";
  const std::string svg = pb::chart_svg(s, {});
  EXPECT_NE(svg.find("nothing here"), std::string::npos);
  EXPECT_EQ(count(svg, "<circle"), 0u);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(BenchChart, PointsSeriesFrontsAndRings) {
  pb::ChartSpec s = spec();
  s.ringed = {"b2"};
  s.goal_ms = 10;
  s.goal_label = "goal 10 ms";
  const std::vector<pb::ChartPoint> pts = {
      {.ms = 2, .error_percent = 5, .series = "a", .label = "a1", .key = "a1", .front = "A"},
      {.ms = 20, .error_percent = 1, .series = "a", .label = "a2", .key = "a2", .front = "A"},
      {.ms = 3, .error_percent = 4, .series = "b", .label = "b1", .key = "b1", .front = "B"},
      {.ms = 30, .error_percent = 2, .series = "b", .label = "b2", .key = "b2", .front = "B"}};
  const std::string svg = pb::chart_svg(s, pts);
  EXPECT_EQ(count(svg, "<circle"), 4u + 2u);              // points + legend entries
  EXPECT_EQ(count(svg, "stroke-dasharray=\"3 3\""), 2u);  // one Pareto front per group
  EXPECT_EQ(count(svg, "stroke=\"black\" stroke-width=\"2\""), 1u);
  EXPECT_NE(svg.find("<title>b2: 30 ms, 2 %</title>"), std::string::npos);
  EXPECT_NE(svg.find("goal 10 ms"), std::string::npos);
  EXPECT_NE(svg.find("title &lt;a &amp; b&gt;"), std::string::npos);  // escaped
}

TEST(BenchChart, PointsAboveTheErrorLimitAreHollowOnTheTopEdge) {
  pb::ChartSpec s = spec();
  s.error_limit = 20;
  const std::vector<pb::ChartPoint> pts = {
      {.ms = 2, .error_percent = 5, .series = "a", .label = "low", .key = "low", .front = ""},
      {.ms = 4, .error_percent = 37, .series = "a", .label = "high", .key = "high", .front = ""}};
  const std::string svg = pb::chart_svg(s, pts);
  EXPECT_EQ(count(svg, "fill-opacity=\"0\""), 1u);
  EXPECT_NE(svg.find("cy=\"50\""), std::string::npos);  // the plot's top edge
  EXPECT_NE(svg.find(">high (37%)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">20</text>"), std::string::npos);  // the axis ends at the limit
  EXPECT_EQ(svg.find(">25</text>"), std::string::npos);
}

pb::LineChartSpec line_spec() {
  pb::LineChartSpec s;
  s.title = "error against n";
  s.x_label = "n";
  s.y_label = "error, %";
  s.x_min = 0;
  s.x_max = 3;
  s.legend_title = "scene, map";
  s.notes = {"a note"};
  return s;
}

TEST(BenchChart, LineChartDrawsOneLinePerSeriesWithMarkersAndALegend) {
  const std::vector<pb::LineSeries> series = {
      {.name = "dem, sky", .x = {0, 1}, .y = {3, 1.1}, .colour = 0, .dash = 0},
      {.name = "sphere, studio + sun",
       .x = {0, 1, 2, 3},
       .y = {15.8, 4.9, 2.7, 2.2},
       .colour = 1,
       .dash = 1},
      {.name = "lonely <one>", .x = {0}, .y = {7}, .colour = 9, .dash = 2}};
  const std::string svg = pb::line_chart_svg(line_spec(), series);
  EXPECT_EQ(count(svg, "<polyline"), 2u);                 // a single point draws no line
  EXPECT_EQ(count(svg, "<circle"), 7u);                   // one marker per point
  EXPECT_EQ(count(svg, "stroke-dasharray=\"6 4\""), 2u);  // the dashed line and its legend entry
  EXPECT_EQ(count(svg, "stroke-dasharray=\"2 3\""), 1u);  // the dotted legend entry only
  EXPECT_NE(svg.find("<title>sphere, studio + sun: x = 3, 2.2</title>"), std::string::npos);
  EXPECT_NE(svg.find(">lonely &lt;one&gt;</text>"), std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#ff7f0e\""), std::string::npos);  // colour 9: palette 1
  for (const char* tick : {">0</text>", ">1</text>", ">2</text>", ">3</text>"})
    EXPECT_NE(svg.find(tick), std::string::npos) << tick;
  EXPECT_NE(svg.find(">15</text>"), std::string::npos);  // y axis: steps of 5 up to 20
  EXPECT_NE(svg.find(">20</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">25</text>"), std::string::npos);
  EXPECT_NE(svg.find(">scene, map</text>"), std::string::npos);
  EXPECT_NE(svg.find(">a note</text>"), std::string::npos);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(BenchChart, LineChartWithoutPointsSaysSo) {
  pb::LineChartSpec s = line_spec();
  s.empty_text = "nothing measured";
  const std::string svg = pb::line_chart_svg(s, {{.name = "empty", .x = {}, .y = {}}});
  EXPECT_NE(svg.find("nothing measured"), std::string::npos);
  EXPECT_EQ(count(svg, "<circle"), 0u);
}

TEST(BenchChart, LineChartRejectsMismatchedSeriesAndAnEmptyRange) {
  try {
    pb::line_chart_svg(line_spec(), {{.name = "bad", .x = {0, 1}, .y = {1}}});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bad'"), std::string::npos) << e.what();
  }
  pb::LineChartSpec s = line_spec();
  s.x_max = s.x_min;
  EXPECT_THROW(pb::line_chart_svg(s, {}), std::invalid_argument);
}

TEST(BenchChart, WriteAtomicallyCreatesTheFolderAndLeavesNoTemporary) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "penumbra_bench_chart_test";
  std::filesystem::remove_all(dir);
  const std::string path = (dir / "sub" / "out.svg").string();
  ASSERT_TRUE(pb::write_atomically(path, "first"));
  ASSERT_TRUE(pb::write_atomically(path, "second"));
  std::ifstream f(path);
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_EQ(text.str(), "second");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove_all(dir);
}

}  // namespace
