// Work a system skipped: each system may report, per frame, how many of its items (terrains,
// tiles, entities, ... its own unit) it worked on and how many it skipped because nothing it
// reads had changed (component versions, stamps). The executor sums the reports of one run of
// a system into its SystemTiming (done, skipped); TimingTable prints them per frame.
//
// Threading: report_work adds to the counter of the system that the calling thread is running
// (run, run_chunk or finish of a system, set by the Executor; atomic, so chunks of one system
// may report in parallel). Call it from those functions themselves, not from inside a
// parallel loop they start: a worker of that loop may be running another system's scope, and
// outside any system (a system function called directly, as tests do) the report is dropped.
#pragma once

#include <atomic>
#include <cstdint>

namespace penumbra::jobs {

// Adds to the current system's counts for this frame (no-op outside the Executor).
void report_work(std::uint64_t done, std::uint64_t skipped);
// One item: done (true) or skipped (false).
inline void report_item(bool done) {
  report_work(done ? 1 : 0, done ? 0 : 1);
}

// One system's counts for one frame; `reported` tells 0 / 0 from "does not report".
struct WorkCounter {
  std::atomic<std::uint64_t> done{0}, skipped{0};
  std::atomic<bool> reported{false};
};

// Makes `counter` the calling thread's current one until destroyed (then the previous one
// again: systems may nest when a waiting thread runs another system's task).
class WorkScope {
 public:
  explicit WorkScope(WorkCounter* counter);
  ~WorkScope();
  WorkScope(const WorkScope&) = delete;
  WorkScope& operator=(const WorkScope&) = delete;

 private:
  WorkCounter* previous_;
};

}  // namespace penumbra::jobs
