#include "penumbra/jobs/work_report.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "penumbra/jobs/executor.h"
#include "penumbra/jobs/frame_report.h"

namespace penumbra::jobs {
namespace {

struct Item {
  int value = 0;
};

const SystemTiming& timing(const FrameStats& f, std::string_view name) {
  for (const SystemTiming& t : f.systems)
    if (t.name == name) return t;
  throw std::runtime_error("no system " + std::string(name));
}

class WorkReportTest : public ::testing::TestWithParam<int> {};

TEST_P(WorkReportTest, TaskChunkAndSilentSystemsPerFrame) {
  ecs::World w;
  for (int i = 0; i < 50000; ++i) w.create_with(Item{i});
  Schedule s;
  s.add_task("task", [](SystemContext& ctx) { ctx.report_work(3, 2); });
  // Every chunk reports its rows, odd values skipped: the sum over chunks run in parallel.
  s.add_chunks<const Item>("chunks", [](SystemContext&, const ecs::ChunkView<const Item>& c) {
    std::uint64_t odd = 0;
    for (const Item& it : c.get<const Item>()) odd += it.value & 1;
    report_work(c.size() - odd, odd);
  });
  s.add_task("silent", [](SystemContext&) {});
  s.add_task("items", [](SystemContext&) {
    report_item(true);
    report_item(false);
    report_item(false);
  });
  Executor ex(GetParam());
  TimingTable table;
  for (int f = 0; f < 3; ++f) {
    const FrameStats& frame = ex.run(s, w);
    table.add(frame);
    const SystemTiming& task = timing(frame, "task");
    EXPECT_TRUE(task.reported);
    EXPECT_EQ(task.done, 3u) << "counts are per frame, not summed over frames";
    EXPECT_EQ(task.skipped, 2u);
    const SystemTiming& chunks = timing(frame, "chunks");
    EXPECT_TRUE(chunks.reported);
    EXPECT_EQ(chunks.done, 25000u);
    EXPECT_EQ(chunks.skipped, 25000u);
    EXPECT_FALSE(timing(frame, "silent").reported);
    EXPECT_EQ(timing(frame, "items").done, 1u);
    EXPECT_EQ(timing(frame, "items").skipped, 2u);
  }
  ASSERT_EQ(table.rows().size(), 4u);
  EXPECT_EQ(table.rows()[0].done, 9u);
  EXPECT_DOUBLE_EQ(table.rows()[0].skipped_per_frame(table.frames()), 2.0);
  std::ostringstream text;
  table.print(text);
  const std::string out = text.str();
  EXPECT_NE(out.find("skipped/f"), std::string::npos) << out;
  const auto silent = out.find("silent");
  ASSERT_NE(silent, std::string::npos);
  const std::string silent_line = out.substr(silent, out.find('\n', silent) - silent);
  EXPECT_NE(silent_line.find(" -"), std::string::npos) << "no report: '-', not 0: " << silent_line;
  const auto task = out.find("task");
  EXPECT_NE(out.substr(task, out.find('\n', task) - task).find("3.0"), std::string::npos) << out;
}

INSTANTIATE_TEST_SUITE_P(Threads, WorkReportTest, ::testing::Values(1, 2, 4));

TEST(WorkReport, OutsideASystemItIsDroppedAndScopesNest) {
  report_work(5, 5);  // no executor: nothing to add to, no crash
  WorkCounter outer, inner;
  {
    const WorkScope a(&outer);
    report_work(1, 0);
    {
      const WorkScope b(&inner);
      report_work(0, 4);
    }
    report_item(false);
  }
  report_work(7, 7);
  EXPECT_EQ(outer.done.load(), 1u);
  EXPECT_EQ(outer.skipped.load(), 1u);
  EXPECT_EQ(inner.done.load(), 0u);
  EXPECT_EQ(inner.skipped.load(), 4u);
  EXPECT_TRUE(inner.reported.load());
}

}  // namespace
}  // namespace penumbra::jobs
