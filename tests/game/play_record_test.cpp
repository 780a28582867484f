// The play benchmark's record: frame statistics, the JSON it writes, child runs.
#include "play_record.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace penumbra::play {
namespace {

TEST(PlayRecord, SummaryUsesNearestRankPercentiles) {
  std::vector<FrameSample> samples;
  for (int i = 1; i <= 20; ++i) samples.push_back({double(i), 0.5 * i, 0.25 * i});
  const FrameSummary s = summarize(samples);
  EXPECT_DOUBLE_EQ(s.mean_ms, 10.5);
  EXPECT_DOUBLE_EQ(s.median_ms, 10.0);  // rank ceil(0.5 * 20) = 10
  EXPECT_DOUBLE_EQ(s.p95_ms, 19.0);     // rank ceil(0.95 * 20) = 19
  EXPECT_NEAR(s.fps, 1000.0 / 10.5, 1e-9);
  EXPECT_DOUBLE_EQ(s.sim_ms, 5.25);
  EXPECT_DOUBLE_EQ(s.render_ms, 2.625);
  const FrameSummary none = summarize({});
  EXPECT_EQ(none.fps, 0.0) << "no frames: zeros, not a division by zero";
}

TEST(PlayRecord, JsonHoldsTheRunAndIgnoresBrokenSplits) {
  PlayRecord r;
  r.scene = "terrain";
  r.frames = 3;
  r.samples = {{20, 8, 12}, {30, 9, 21}, {25, 7, 18}};
  r.empty_frame_ms = 5;
  r.empty_frame_before_ms = 4.5;
  r.empty_frame_after_ms = 5.5;
  r.gpu_timed_frames = 40;
  r.terrain_triangles = 1234;
  r.lavapipe_threads = "2";
  r.environment_tiles_per_frame = 74.5;
  r.environment_stale_per_frame = 289.0;
  r.systems = {{"terrain_shadow.lights", 1.5, 3.0, true, 2.0, 398.0}, {"motion", 0.1, 0.2}};
  PlayRecord child = r;
  child.sim_threads = 1;
  r.splits = {to_json(child), "{ not json", ""};
  const nlohmann::json j = nlohmann::json::parse(to_json(r));
  EXPECT_EQ(j["format"], "penumbra-play");
  EXPECT_EQ(j["version"], 1);
  EXPECT_DOUBLE_EQ(j["frame"]["median_ms"].get<double>(), 25.0);
  EXPECT_DOUBLE_EQ(j["frame"]["x_empty_frame"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(j["frame"]["empty_frame_after_ms"].get<double>(), 5.5);
  EXPECT_EQ(j["run"]["gpu_timed_frames"], 40);
  EXPECT_EQ(j["terrain"]["triangles"], 1234);
  EXPECT_EQ(j["threads"]["lavapipe"], "2");
  EXPECT_DOUBLE_EQ(j["environment"]["tiles_per_frame"].get<double>(), 74.5);
  EXPECT_DOUBLE_EQ(j["environment"]["stale_per_frame"].get<double>(), 289.0);
  ASSERT_EQ(j["systems"].size(), 2u);
  EXPECT_EQ(j["systems"][0]["name"], "terrain_shadow.lights");
  EXPECT_DOUBLE_EQ(j["systems"][0]["skipped_per_frame"].get<double>(), 398.0);
  EXPECT_TRUE(j["systems"][1]["done_per_frame"].is_null()) << "a system that does not report";
  ASSERT_EQ(j["splits"].size(), 1u) << "a split whose output is not a record is left out";
  EXPECT_EQ(j["splits"][0]["threads"]["simulation"], 1);
}

TEST(PlayRecord, MachineFactsAreRead) {
  PlayRecord r;
  describe_machine(r);
  EXPECT_GT(r.cores, 0);
  EXPECT_GE(r.load_average, 0.0);
  EXPECT_EQ(r.date.size(), 20u) << r.date;  // 2026-12-01T20:00:00Z
}

// Run by the next test in a child process: fails unless the child got "yes".
TEST(PlayRecord, ChildSeesItsEnvironment) {
  const char* v = std::getenv("PENUMBRA_CHILD_EXPECT");
  if (v) {
    EXPECT_STREQ(v, "yes");
  }
}

TEST(PlayRecord, ChildRunsGetTheirEnvironmentAndReportTheirStatus) {
  const std::vector<std::string> args = {"--gtest_filter=PlayRecord.ChildSeesItsEnvironment"};
  EXPECT_EQ(run_child(args, "PENUMBRA_CHILD_EXPECT=yes"), 0);
  EXPECT_EQ(run_child(args, "PENUMBRA_CHILD_EXPECT=no"), 1);
}

}  // namespace
}  // namespace penumbra::play
