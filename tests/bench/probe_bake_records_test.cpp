// The probe_bake group's records and chart (probe_bake_records.h): the sweep's cases, the
// Pareto front, the records file and the charts' points.
#include "probe_bake_records.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

namespace {

namespace pbr = penumbra::bench::probe_bake;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

pbr::Record sweep(const std::string& key, const std::string& method, double ms, double err) {
  pbr::Record r;
  r.key = key;
  r.kind = "sweep";
  r.scene = "room";
  r.method = method;
  r.ms = ms;
  r.rel_rms_error = err;
  r.probes = 100;
  return r;
}

TEST(ProbeBakeRecords, SweepCasesAreTheAccuracyTestsMethods) {
  const auto& cases = pbr::sweep_cases();
  ASSERT_EQ(cases.size(), 15u);
  std::set<std::string> keys;
  int grid = 0, spawn = 0, gradient = 0, edges = 0;
  for (const pbr::SweepCase& c : cases) {
    keys.insert(c.key);
    EXPECT_EQ(c.key.rfind("BM_PlacementSweep/", 0), 0u) << c.key;
    EXPECT_GT(c.spacing, 0) << c.key;
    EXPECT_EQ(c.spawn > 0, c.method.starts_with("spawn-merge")) << c.key;
    EXPECT_EQ(c.edge_rays, c.method.ends_with(" + edge rays")) << c.key;
    grid += c.method == "grid";
    spawn += c.method == "spawn-merge";
    gradient += c.method == "gradient";
    edges += c.edge_rays;
  }
  EXPECT_EQ(keys.size(), cases.size());  // unique keys
  EXPECT_EQ(grid, 4);
  EXPECT_EQ(spawn, 4);
  EXPECT_EQ(gradient, 3);
  EXPECT_EQ(edges, 4);
  EXPECT_TRUE(keys.count("BM_PlacementSweep/grid_0.75m"));
  EXPECT_TRUE(keys.count("BM_PlacementSweep/spawn_merge_1m/spawn:0.7"));
}

TEST(ProbeBakeRecords, ParetoFront) {
  std::vector<pbr::Record> r = {
      sweep("fast", "grid", 10, 0.5),        // front: fastest
      sweep("slow", "grid", 100, 0.1),       // front: most accurate
      sweep("worse", "gradient", 50, 0.6),   // dominated by "fast"
      sweep("mid", "spawn-merge", 20, 0.3),  // front
      sweep("tie", "spawn-merge", 20, 0.3),  // equal to "mid": neither dominates
  };
  pbr::Record bake;
  bake.key = "BM_Bake/room";
  bake.kind = "bake";
  bake.ms = 1;  // not a sweep point: never on the front
  r.push_back(bake);
  pbr::mark_pareto_front(r);
  EXPECT_TRUE(r[0].pareto_front);
  EXPECT_TRUE(r[1].pareto_front);
  EXPECT_FALSE(r[2].pareto_front);
  EXPECT_TRUE(r[3].pareto_front);
  EXPECT_TRUE(r[4].pareto_front);
  EXPECT_FALSE(r[5].pareto_front);
}

TEST(ProbeBakeRecords, RecordsJson) {
  std::vector<pbr::Record> r = {sweep("BM_PlacementSweep/grid_1m", "grid", 150, 0.28)};
  r[0].dark_side = 0.154;
  r[0].params_json = "{\"spacing\": 1}";
  r[0].counters = {{"probes", 312}, {"rel_rms_error", 0.28}};
  pbr::Record floor;
  floor.key = "BM_RaysFirstHit/room/threads:2";
  floor.kind = "floor";
  floor.method = "say \"hi\"";  // escaped
  r.push_back(floor);
  pbr::RunInfo info;
  info.cpus = 2;
  info.load_avg_at_end = {1.25, 2, 3.5};
  const std::string j = pbr::records_json(r, info);
  EXPECT_NE(j.find("\"group\": \"probe_bake\""), std::string::npos);
  EXPECT_NE(j.find("\"load_avg_at_end\": [1.25, 2, 3.5]"), std::string::npos);
  EXPECT_NE(j.find("\"reference_seconds\": null"), std::string::npos);
  EXPECT_NE(j.find("\"params\": {\"spacing\": 1}"), std::string::npos);
  EXPECT_NE(j.find("\"dark_side\": 0.154, \"lit_side\": null"), std::string::npos);
  EXPECT_NE(j.find("\"counters\": {\"probes\": 312, \"rel_rms_error\": 0.28}"), std::string::npos);
  EXPECT_NE(j.find("\"method\": \"say \\\"hi\\\"\""), std::string::npos);
  EXPECT_EQ(count(j, "\"case\": "), 2u);
  EXPECT_EQ(count(j, "{"), count(j, "}"));
  EXPECT_EQ(count(j, "["), count(j, "]"));
}

TEST(ProbeBakeRecords, ChartHasOneSeriesPerMethodAndOnlySweepPoints) {
  std::vector<pbr::Record> r = {
      sweep("BM_PlacementSweep/grid_2m", "grid", 20, 0.5),
      sweep("BM_PlacementSweep/grid_1m", "grid", 150, 0.28),
      sweep("BM_PlacementSweep/spawn_merge_2m/spawn:0.7", "spawn-merge", 400, 0.45),
      sweep("BM_PlacementSweep/gradient_1m", "gradient", 500, 0.46),
  };
  r.push_back(sweep("no_error", "grid", 10, 0));
  r.back().rel_rms_error.reset();  // no error: not drawn
  pbr::Record bake = sweep("BM_Bake/room", "grid", 140, 0.1);
  bake.kind = "bake";  // not a sweep point: not drawn
  r.push_back(bake);
  const auto pts = pbr::chart_points(r);
  ASSERT_EQ(pts.size(), 4u);
  std::set<std::string> series;
  for (const auto& p : pts) series.insert(p.series);
  EXPECT_EQ(series, (std::set<std::string>{"grid", "spawn-merge", "gradient"}));
  EXPECT_EQ(pts[0].label, "2 m, 100");
  EXPECT_EQ(pts[2].label, "2 m/0.7, 100");
  EXPECT_DOUBLE_EQ(pts[1].error_percent, 28);
  const std::string svg = pbr::chart(r);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
  EXPECT_NE(svg.find("BM_PlacementSweep/gradient_1m"), std::string::npos);
  EXPECT_EQ(count(svg, "stroke=\"black\" stroke-width=\"2\""), 1u);  // the default ringed
  EXPECT_EQ(svg.find("BM_Bake/room"), std::string::npos);
  // The probe-count chart: the same points, its axis the probes.
  r[1].probes = 312;
  const std::string by_probes = pbr::probes_chart(r);
  EXPECT_NE(by_probes.find("probes in the cloud (log)"), std::string::npos);
  EXPECT_NE(by_probes.find("BM_PlacementSweep/grid_1m"), std::string::npos);
  EXPECT_EQ(by_probes.find("BM_Bake/room"), std::string::npos);
  EXPECT_NE(by_probes, svg);
}

}  // namespace
