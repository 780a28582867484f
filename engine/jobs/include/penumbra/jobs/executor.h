// Executor: runs a Schedule's graph for one frame on oneTBB.
//
// Inside a task_arena of threads() slots, each node starts when its predecessors finish; ready
// nodes are spawned into a tbb::task_group (one runs inline on the thread that freed it). A
// chunk system is a tbb::parallel_for over its chunks with a grain chosen from the previous
// frame's time per chunk, so each task holds about kTargetTaskNs of work.
//
// Determinism: component data after a frame does not depend on threads(): systems that
// conflict are ordered, a chunk is processed by exactly one task, command buffers are applied
// in (system, chunk, sequence) order, and add_reduce combines per-chunk partials in chunk order.
//
// Threading: run() is called by one thread at a time; it blocks until the frame is done.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "penumbra/ecs/command_buffer.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::jobs {

struct SystemTiming {
  std::string_view name;
  bool sync = false;
  std::int64_t start_ns = 0;  // from the frame's start
  std::int64_t duration_ns = 0;
  std::size_t entities = 0;
  std::size_t chunks = 0;
  int thread = 0;  // arena slot that started the system
  // Items the system worked on and skipped as unchanged this frame (jobs::report_work);
  // reported == false: the system does not report.
  std::uint64_t done = 0, skipped = 0;
  bool reported = false;
  bool paused = false;  // Schedule::set_paused: it ran nothing this frame
};

// One parallel-for task of a chunk system (recorded when task tracing is on).
struct TaskSpan {
  std::uint32_t node = 0;
  int thread = 0;
  std::int64_t start_ns = 0;
  std::int64_t duration_ns = 0;
  std::size_t first_chunk = 0;
  std::size_t chunk_count = 0;
};

struct FrameStats {
  std::int64_t frame_ns = 0;
  int threads = 1;
  std::vector<SystemTiming> systems;  // in node order
  std::vector<TaskSpan> tasks;
  ecs::ApplyStats commands;
};

class Executor {
 public:
  static constexpr std::int64_t kTargetTaskNs = 50'000;

  // threads == 0: one per hardware thread.
  explicit Executor(int threads = 0);
  ~Executor();
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  int threads() const;
  void set_trace_tasks(bool on);

  // Runs one frame of `schedule` over `world` (building the schedule first if needed).
  const FrameStats& run(Schedule& schedule, ecs::World& world);
  const FrameStats& last_frame() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::jobs
