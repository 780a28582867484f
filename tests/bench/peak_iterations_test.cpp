// PeakIterations (peak_iterations.h): which timed iteration of the vector peak stands for all the
// threads together.
#include "peak_iterations.h"

#include <gtest/gtest.h>

namespace penumbra::terrain_bench {
namespace {

TEST(PeakIterations, TheBestIterationThatEveryThreadRan) {
  // A faster iteration that one thread ran alone does not count while one with both exists.
  PeakIterations peak(2);
  peak.add(900.0, 2);
  peak.add(600.0, 1);
  peak.add(850.0, 2);
  peak.add(1000.0, 2);
  EXPECT_DOUBLE_EQ(peak.best_ns(), 850.0);
  EXPECT_EQ(peak.threads_seen(), 2);
}

TEST(PeakIterations, WithoutOneThatEveryThreadRanTheBestScaledToAllThreads) {
  // A vCPU stopped through the whole measurement: every iteration ran on one thread of two, so
  // the best one's time per thread stands for both (half of it), and the count says so.
  PeakIterations peak(2);
  peak.add(1900.0, 1);
  peak.add(1800.0, 1);
  peak.add(2100.0, 1);
  EXPECT_DOUBLE_EQ(peak.best_ns(), 900.0);
  EXPECT_EQ(peak.threads_seen(), 1);
}

TEST(PeakIterations, OneThreadAndZeroThreadsSeen) {
  PeakIterations one(1);
  one.add(500.0, 1);
  EXPECT_DOUBLE_EQ(one.best_ns(), 500.0);
  EXPECT_EQ(one.threads_seen(), 1);
  PeakIterations none(4);  // no thread index recorded: counted as one
  none.add(800.0, 0);
  EXPECT_DOUBLE_EQ(none.best_ns(), 200.0);
  EXPECT_EQ(none.threads_seen(), 1);
}

}  // namespace
}  // namespace penumbra::terrain_bench
