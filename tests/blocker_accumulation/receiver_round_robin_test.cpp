#include "penumbra/systems/blocker_accumulation/receiver_round_robin.h"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include "common/stability.h"

namespace penumbra::blocker_accumulation {
namespace {

struct Entity {
  int id;
  std::size_t points;
  bool shaded;
};

std::vector<int> ids(const std::vector<Entity>& v) {
  std::vector<int> out;
  for (const Entity& e : v) out.push_back(e.id);
  return out;
}

auto is_new = [](const Entity& e) { return !e.shaded; };
auto points = [](const Entity& e) { return e.points; };

TEST(PickReceivers, NewOnesFirstThenRoundRobinWithinTheBudget) {
  const std::vector<Entity> all = {{0, 100, true}, {1, 100, false}, {2, 100, true}, {3, 100, true}};
  std::uint64_t cursor = 0;
  // The new one (100 points) and then shaded ones from the cursor until 250 points are reached.
  EXPECT_EQ(ids(pick_receivers(all, 250, cursor, is_new, points)), (std::vector<int>{1, 0, 2}));
  EXPECT_EQ(cursor, 2u);
  // From the cursor on: entity 2 is next, none skipped (an earlier version indexed with the
  // cursor it was advancing and stepped over every other entity).
  EXPECT_EQ(ids(pick_receivers(all, 150, cursor, is_new, points)), (std::vector<int>{1, 2}));
  EXPECT_EQ(cursor, 3u);
  EXPECT_EQ(ids(pick_receivers(all, 150, cursor, is_new, points)), (std::vector<int>{1, 3}));
  EXPECT_EQ(cursor, 4u);
}

TEST(PickReceivers, ZeroBudgetIsEveryoneAndATinyBudgetStillShadesOne) {
  PENUMBRA_STABILITY("a receiver budget of 0, of 1 point; no receivers",
                     "0: every receiver; 1: still one a frame; none: nothing", "-");
  const std::vector<Entity> all = {{0, 500, true}, {1, 500, true}};
  std::uint64_t cursor = 1;
  EXPECT_EQ(ids(pick_receivers(all, 0, cursor, is_new, points)), (std::vector<int>{1, 0}));
  EXPECT_EQ(cursor, 3u);
  EXPECT_EQ(ids(pick_receivers(all, 1, cursor, is_new, points)), (std::vector<int>{1}));
  EXPECT_TRUE(pick_receivers(std::vector<Entity>{}, 10, cursor, is_new, points).empty());
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
