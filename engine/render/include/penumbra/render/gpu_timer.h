// GPU timestamps per pass, and a table accumulating them over frames.
//
// GpuTimer: one query pool per frame in flight. start() writes the frame's first timestamp;
// mark(name) writes the next one, and the pass `name` is the work between the two: marks are
// written with vkCmdWriteTimestamp2 at ALL_COMMANDS, i.e. once all earlier commands are done,
// so a pass's time is from the end of the previous pass to the end of its own. read() is
// called after the frame's fence and returns that frame's times. On devices without
// timestamps every call is a no-op and read() returns nothing.
//
// CPU devices (lavapipe): lavapipe flushes its llvmpipe scene before a timestamp, and llvmpipe
// writes the timestamp from the rasterizer threads in every tile of the scene it lands in; the
// value is taken when the last tile reaches it. Followed by more draws in the same scene, a mark
// would read as the end of those draws. So on CPU devices every mark is followed by a second,
// ignored timestamp, whose flush leaves the mark alone in its scene: it is then written right
// after the previous scene's rasterization completed. Nothing waits on the CPU, frames stay
// pipelined (measured cost: see the render benchmark).
//
// PassTimingTable: mean / max per pass name, in first-seen order, printed with the CPU table.
//
// Threading: render thread only.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "penumbra/render/resources.h"

namespace penumbra::render {

struct PassTime {
  const char* name = "";  // a string literal owned by the pass
  double ms = 0;
};

class GpuTimer {
 public:
  GpuTimer(Device& device, std::uint32_t max_passes = 16);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // First thing in the frame's command buffer. With `enabled` false the frame is not timed:
  // mark() records nothing and read() returns nothing for it.
  void start(VkCommandBuffer cmd, bool enabled = true);
  void mark(VkCommandBuffer cmd, const char* name);
  bool enabled() const { return enabled_; }
  // The recorded passes of the frame (its fence must have signalled). Clears the record.
  std::vector<PassTime> read();

 private:
  void stamp(VkCommandBuffer cmd, std::uint32_t index);

  Device* device_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  std::uint32_t capacity_;
  std::vector<const char*> names_;
  double ns_per_tick_;
  bool isolate_ = false;  // CPU device: a second timestamp after each mark (see above)
  bool enabled_ = false;  // this frame is timed
};

class PassTimingTable {
 public:
  void add(std::span<const PassTime> frame);
  // Columns: pass, mean ms, max ms, share of the GPU frame.
  void print(std::ostream& out) const;
  std::size_t frames() const { return frames_; }
  double mean_total_ms() const;
  struct Row {
    std::string name;
    double total_ms = 0, max_ms = 0;
    std::size_t count = 0;
  };
  const std::vector<Row>& rows() const { return rows_; }
  // Mean ms of `name`, 0 when never seen.
  double mean_ms(const std::string& name) const;
  void clear();

 private:
  std::vector<Row> rows_;
  std::size_t frames_ = 0;
};

}  // namespace penumbra::render
