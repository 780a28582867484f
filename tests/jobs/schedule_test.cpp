#include "penumbra/jobs/schedule.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include "common/stability.h"

// Named (not anonymous) namespace: the DOT snapshot spells type names the same on every compiler.
namespace penumbra::jobs::schedule_test {
struct Position {};
struct Velocity {};
struct Light {};
struct Stats {};
struct Dead {};
}  // namespace penumbra::jobs::schedule_test

namespace penumbra::jobs {
namespace {

using namespace schedule_test;

bool has_edge(const Schedule& s, const std::string& from, const std::string& to) {
  const auto& nodes = s.nodes();
  for (const auto& n : nodes) {
    if (n.system->name != from) continue;
    for (auto succ : n.successors) {
      if (nodes[succ].system->name == to) return true;
    }
  }
  return false;
}

void noop(SystemContext&) {}

TEST(Schedule, ReadersShareWritersOrder) {
  Schedule s;
  s.add_task("read_a", noop).reads<Position>();
  s.add_task("read_b", noop).reads<Position>();
  s.add_task("write", noop).writes<Position>();
  s.add_task("read_c", noop).reads<Position>();
  s.build();
  EXPECT_FALSE(has_edge(s, "read_a", "read_b"));
  EXPECT_TRUE(has_edge(s, "read_a", "write"));
  EXPECT_TRUE(has_edge(s, "read_b", "write"));
  EXPECT_TRUE(has_edge(s, "write", "read_c"));
  EXPECT_TRUE(s.conflicts().empty());
}

TEST(Schedule, DisjointSystemsAreIndependent) {
  Schedule s;
  s.add_task("motion", noop).writes<Position>();
  s.add_task("lights", noop).writes<Light>();
  s.build();
  for (const auto& n : s.nodes()) EXPECT_TRUE(n.successors.empty());
}

TEST(Schedule, EdgesAreTransitivelyReduced) {
  Schedule s;
  s.add_task("a", noop).writes<Position>();
  s.add_task("b", noop).writes<Position>();
  s.add_task("c", noop).writes<Position>();
  s.build();
  EXPECT_TRUE(has_edge(s, "a", "b"));
  EXPECT_TRUE(has_edge(s, "b", "c"));
  EXPECT_FALSE(has_edge(s, "a", "c")) << "implied by a -> b -> c";
}

TEST(Schedule, SyncPointBeforeFirstSystemThatSeesStructuralChanges) {
  Schedule s;
  s.add_task("kill", noop).reads<Position>().structural<Dead>();
  s.add_task("lights", noop).writes<Light>();  // does not touch Dead: runs before the sync
  s.add_task("reap", noop).reads<Dead>();
  s.build();
  ASSERT_EQ(s.nodes().size(), 4u);
  EXPECT_TRUE(has_edge(s, "kill", "sync before reap"));
  EXPECT_TRUE(has_edge(s, "lights", "sync before reap"));
  EXPECT_TRUE(has_edge(s, "sync before reap", "reap"));
}

TEST(Schedule, SpawningSystemGetsEndOfFrameSync) {
  Schedule s;
  s.add_task("spawner", noop).spawns();
  s.add_task("stats", noop).writes<Stats>();
  s.build();
  EXPECT_EQ(s.nodes().back().system->name, "sync: end of frame");
  EXPECT_EQ(s.nodes().back().system->kind, System::Kind::kSync);
}

TEST(Schedule, ExplicitOrderingReportsUnorderedConflicts) {
  Schedule s(Schedule::Ordering::kExplicit);
  s.add_task("move", noop).writes<Position>();
  s.add_task("wind", noop).writes<Position>();
  s.add_task("draw", noop).reads<Position>().after("move").after("wind");
  s.add_task("lights", noop).writes<Light>();
  s.build();
  const auto c = s.conflicts();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].first, "move");
  EXPECT_EQ(c[0].second, "wind");
  EXPECT_TRUE(has_edge(s, "move", "wind")) << "serialised in registration order";
}

TEST(Schedule, ExplicitConstraintsCanReorderRegistration) {
  Schedule s(Schedule::Ordering::kExplicit);
  s.add_task("late", noop).writes<Position>();
  s.add_task("early", noop).writes<Position>().before("late");
  s.build();
  EXPECT_EQ(s.nodes().front().system->name, "early");
  EXPECT_TRUE(s.conflicts().empty());
}

TEST(Schedule, RejectsCyclesUnknownNamesAndDuplicates) {
  PENUMBRA_STABILITY("a cycle, an unknown name in after()/before(), a duplicate name",
                     "std::invalid_argument at build()", "-");
  {
    Schedule s;
    s.add_task("a", noop).after("b");
    s.add_task("b", noop).after("a");
    EXPECT_THROW(s.build(), std::invalid_argument);
  }
  {
    Schedule s;
    s.add_task("a", noop).after("nobody");
    EXPECT_THROW(s.build(), std::invalid_argument);
  }
  {
    Schedule s;
    s.add_task("a", noop);
    s.add_task("a", noop);
    EXPECT_THROW(s.build(), std::invalid_argument);
  }
}

// Snapshot of the graph for a known frame: the edges a change to the scheduler must keep.
TEST(Schedule, DotSnapshot) {
  Schedule s;
  s.add_task("input", noop).writes<Velocity>();
  s.add_each<Position, const Velocity>("integrate", [](Position&, const Velocity&) {});
  s.add_task("lights", noop).writes<Light>();
  s.add_task("cull", noop).reads<Position>().structural<Dead>();
  s.add_task("stats", noop).reads<Position, Light>().writes<Stats>();
  s.add_task("reap", noop).reads<Dead>().spawns();
  s.build();
  const std::string expected = R"(digraph schedule {
  rankdir=LR;
  node [shape=box, fontname="monospace"];
  n0 [label="input\nW: penumbra::jobs::schedule_test::Velocity"];
  n1 [label="integrate\nR: penumbra::jobs::schedule_test::Velocity\nW: penumbra::jobs::schedule_test::Position"];
  n2 [label="lights\nW: penumbra::jobs::schedule_test::Light"];
  n3 [label="cull\nR: penumbra::jobs::schedule_test::Position\n+ adds/removes: penumbra::jobs::schedule_test::Dead"];
  n4 [label="stats\nR: penumbra::jobs::schedule_test::Light, penumbra::jobs::schedule_test::Position\nW: penumbra::jobs::schedule_test::Stats"];
  n5 [label="sync before reap", shape=diamond];
  n6 [label="reap\nR: penumbra::jobs::schedule_test::Dead\n+ spawns"];
  n7 [label="sync: end of frame", shape=diamond];
  n0 -> n1;
  n1 -> n3;
  n1 -> n4;
  n2 -> n4;
  n3 -> n5;
  n4 -> n5;
  n5 -> n6;
  n6 -> n7;
}
)";
  EXPECT_EQ(s.to_dot(), expected);
}

}  // namespace
}  // namespace penumbra::jobs
