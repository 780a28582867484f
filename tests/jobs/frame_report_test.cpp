#include "penumbra/jobs/frame_report.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "penumbra/components/motion.h"

namespace penumbra::jobs {
namespace {

using components::Position;
using components::Velocity;

std::size_t count(const std::string& s, const std::string& needle) {
  std::size_t n = 0;
  for (auto p = s.find(needle); p != std::string::npos; p = s.find(needle, p + 1)) ++n;
  return n;
}

TEST(FrameReport, TimingTableAndTraceNameEverySystem) {
  ecs::World w;
  for (int i = 0; i < 20000; ++i) w.create_with(Position{}, Velocity{1, 0, 0});
  Schedule s;
  s.add_each<Position, const Velocity>("integrate",
                                       [](Position& p, const Velocity& v) { p.x += v.x; });
  s.add_each<const Position>("observe", [](const Position&) {});
  Executor ex(2);
  ex.set_trace_tasks(true);
  TimingTable table;
  std::vector<FrameStats> frames;
  for (int f = 0; f < 4; ++f) {
    table.add(ex.run(s, w));
    frames.push_back(ex.last_frame());
  }
  EXPECT_EQ(table.frames(), 4u);
  ASSERT_EQ(table.rows().size(), 2u);
  EXPECT_EQ(table.rows()[0].name, "integrate");
  EXPECT_EQ(table.rows()[0].entities, 20000u);
  EXPECT_GT(table.rows()[0].total_ms, 0.0);

  std::ostringstream text;
  table.print(text);
  EXPECT_NE(text.str().find("integrate"), std::string::npos);
  EXPECT_NE(text.str().find("observe"), std::string::npos);

  const std::string json = chrome_trace_json(frames);
  EXPECT_EQ(json.rfind("{\"displayTimeUnit\"", 0), 0u);
  EXPECT_EQ(count(json, "\"cat\":\"frame\""), 4u);
  EXPECT_EQ(count(json, "\"name\":\"integrate\",\"cat\":\"system\""), 4u);
  EXPECT_GE(count(json, "\"cat\":\"task\""), 4u) << "parallel-for tasks are traced";
  EXPECT_EQ(count(json, "{"), count(json, "}"));
}

}  // namespace
}  // namespace penumbra::jobs
