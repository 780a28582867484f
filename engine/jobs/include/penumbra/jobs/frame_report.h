// Reports over executed frames: a per-system timing table, Chrome trace JSON (open it in
// Perfetto or chrome://tracing) and, with the schedule, a DOT drawing (Schedule::to_dot).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "penumbra/jobs/executor.h"

namespace penumbra::jobs {

// Accumulates FrameStats over many frames, per system (by node position).
class TimingTable {
 public:
  void add(const FrameStats& frame);
  // Columns: system, mean ms, max ms, share of frame, entities (last frame), chunks, and the
  // items done and skipped as unchanged per frame (mean; "-" for systems that do not report,
  // work_report.h).
  void print(std::ostream& out) const;
  std::size_t frames() const { return frames_; }
  double mean_frame_ms() const;

  struct Row {
    std::string name;
    bool sync = false;
    double total_ms = 0, max_ms = 0;
    std::size_t entities = 0, chunks = 0;
    std::uint64_t done = 0, skipped = 0;  // totals over the frames (jobs::report_work)
    bool reported = false;                // reported in any frame
    double done_per_frame(std::size_t frames) const;
    double skipped_per_frame(std::size_t frames) const;
  };
  const std::vector<Row>& rows() const { return rows_; }

 private:
  std::vector<Row> rows_;
  std::size_t frames_ = 0;
  double frame_total_ms_ = 0;
};

// Chrome trace-event JSON ("X" complete events): one track per worker slot, one slice per
// system run and, when recorded, per parallel-for task. Frames are laid end to end.
std::string chrome_trace_json(std::span<const FrameStats> frames);

}  // namespace penumbra::jobs
