#include "penumbra/jobs/frame_report.h"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <sstream>

namespace penumbra::jobs {
namespace {
std::string json_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}
}  // namespace

void TimingTable::add(const FrameStats& frame) {
  if (rows_.size() != frame.systems.size()) {
    rows_.assign(frame.systems.size(), Row{});
    frames_ = 0;
    frame_total_ms_ = 0;
  }
  for (std::size_t i = 0; i < frame.systems.size(); ++i) {
    const SystemTiming& t = frame.systems[i];
    Row& r = rows_[i];
    const double ms = static_cast<double>(t.duration_ns) * 1e-6;
    r.name = t.name;
    r.sync = t.sync;
    r.total_ms += ms;
    r.max_ms = std::max(r.max_ms, ms);
    r.entities = t.entities;
    r.chunks = t.chunks;
    r.done += t.done;
    r.skipped += t.skipped;
    r.reported = r.reported || t.reported;
  }
  frame_total_ms_ += static_cast<double>(frame.frame_ns) * 1e-6;
  ++frames_;
}

double TimingTable::Row::done_per_frame(std::size_t frames) const {
  return frames == 0 ? 0.0 : static_cast<double>(done) / static_cast<double>(frames);
}

double TimingTable::Row::skipped_per_frame(std::size_t frames) const {
  return frames == 0 ? 0.0 : static_cast<double>(skipped) / static_cast<double>(frames);
}

double TimingTable::mean_frame_ms() const {
  return frames_ == 0 ? 0.0 : frame_total_ms_ / static_cast<double>(frames_);
}

void TimingTable::print(std::ostream& out) const {
  char line[256];
  std::snprintf(line, sizeof line, "%-34s %10s %10s %7s %10s %7s %10s %10s\n", "system", "mean ms",
                "max ms", "frame%", "entities", "chunks", "done/f", "skipped/f");
  out << line;
  const double n = static_cast<double>(std::max<std::size_t>(frames_, 1));
  for (const Row& r : rows_) {
    const double mean = r.total_ms / n;
    char done[32] = "-", skipped[32] = "-";
    if (r.reported) {
      std::snprintf(done, sizeof done, "%.1f", r.done_per_frame(frames_));
      std::snprintf(skipped, sizeof skipped, "%.1f", r.skipped_per_frame(frames_));
    }
    std::snprintf(line, sizeof line, "%-34.34s %10.4f %10.4f %6.1f%% %10zu %7zu %10s %10s\n",
                  r.name.c_str(), mean, r.max_ms,
                  mean_frame_ms() > 0 ? 100.0 * mean / mean_frame_ms() : 0.0, r.entities, r.chunks,
                  done, skipped);
    out << line;
  }
  std::snprintf(line, sizeof line, "%-34s %10.4f   (%zu frames; systems may overlap in time)\n",
                "frame", mean_frame_ms(), frames_);
  out << line;
}

std::string chrome_trace_json(std::span<const FrameStats> frames) {
  std::ostringstream out;
  out << "{\"displayTimeUnit\":\"ns\",\"traceEvents\":[\n";
  bool first = true;
  auto event = [&](std::string_view name, std::string_view cat, int tid, double ts_us,
                   double dur_us, const std::string& args) {
    out << (first ? "" : ",\n") << "{\"name\":\"" << json_escape(name) << "\",\"cat\":\"" << cat
        << "\",\"ph\":\"X\",\"pid\":1,\"tid\":" << tid << ",\"ts\":" << ts_us
        << ",\"dur\":" << dur_us << ",\"args\":{" << args << "}}";
    first = false;
  };
  double origin_us = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const FrameStats& frame = frames[f];
    event("frame " + std::to_string(f), "frame", 1000, origin_us,
          static_cast<double>(frame.frame_ns) * 1e-3, "");
    for (const SystemTiming& s : frame.systems) {
      event(s.name, s.sync ? "sync" : "system", s.thread,
            origin_us + static_cast<double>(s.start_ns) * 1e-3,
            static_cast<double>(s.duration_ns) * 1e-3,
            "\"entities\":" + std::to_string(s.entities) +
                ",\"chunks\":" + std::to_string(s.chunks) +
                (s.reported ? ",\"done\":" + std::to_string(s.done) +
                                  ",\"skipped\":" + std::to_string(s.skipped)
                            : std::string()));
    }
    for (const TaskSpan& t : frame.tasks) {
      event(frame.systems[t.node].name, "task", t.thread,
            origin_us + static_cast<double>(t.start_ns) * 1e-3,
            static_cast<double>(t.duration_ns) * 1e-3,
            "\"first_chunk\":" + std::to_string(t.first_chunk) +
                ",\"chunks\":" + std::to_string(t.chunk_count));
    }
    origin_us += static_cast<double>(frame.frame_ns) * 1e-3;
  }
  out << "\n]}\n";
  return out.str();
}

}  // namespace penumbra::jobs
