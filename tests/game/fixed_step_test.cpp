// Real time in fixed steps (fixed_step.h).
#include "penumbra/game/fixed_step.h"

#include <gtest/gtest.h>

namespace penumbra::game {
namespace {

TEST(FixedStepClock, StepsFollowTheWallClockAtAnyFrameRate) {
  for (double fps : {20.0, 30.0, 60.0, 144.0}) {
    FixedStepClock clock(1.0 / 30.0);
    int steps = clock.steps(0.0);
    EXPECT_EQ(steps, 1) << "the first frame draws a step";
    for (int f = 0; f < static_cast<int>(10 * fps); ++f) steps += clock.steps(1.0 / fps);
    EXPECT_NEAR(steps, 301, 1) << fps << " fps: ten seconds are 300 steps";
  }
}

TEST(FixedStepClock, ASlowFrameRunsAtMostTheCapAndForgetsTheRest) {
  FixedStepClock clock(0.1, 4);
  EXPECT_EQ(clock.steps(0.0), 1);
  EXPECT_EQ(clock.steps(2.0), 4);   // 20 owed
  EXPECT_EQ(clock.steps(0.05), 0);  // the debt was dropped: half a step owed now
  EXPECT_EQ(clock.steps(0.05), 1);
  EXPECT_EQ(clock.steps(-1.0), 0);  // a clock going backwards owes nothing
}

}  // namespace
}  // namespace penumbra::game
