// The vector peak's choice among its timed iterations (baselines_bench.cpp): the peak is what all
// of an arena's threads do together, so its best iteration is taken among those that every thread
// took part in. The host can stop a vCPU for longer than the whole measurement
// (docs/terrain_shadow_log.md, "Twentieth round": one run of 42 read half the peak); when no
// iteration saw every thread, the best one stands in at its rate per thread times the threads,
// and `threads_seen` says how many it saw.
#pragma once

#include <algorithm>

namespace penumbra::terrain_bench {

class PeakIterations {
 public:
  explicit PeakIterations(int threads) : threads_(std::max(threads, 1)) {}

  // One iteration: its time and how many distinct threads ran part of it.
  void add(double ns, int threads_seen) {
    if (threads_seen >= threads_) best_all_ = std::min(best_all_, ns);
    if (ns < best_any_) best_any_ = ns, best_any_threads_ = std::max(threads_seen, 1);
  }
  // The iteration time that stands for all the threads together.
  double best_ns() const { return all() ? best_all_ : best_any_ * best_any_threads_ / threads_; }
  // The threads the chosen iteration saw (all of them unless none did).
  int threads_seen() const { return all() ? threads_ : best_any_threads_; }

 private:
  bool all() const { return best_all_ < kNone; }
  static constexpr double kNone = 1e300;
  int threads_;
  double best_all_ = kNone, best_any_ = kNone;
  int best_any_threads_ = 1;
};

}  // namespace penumbra::terrain_bench
