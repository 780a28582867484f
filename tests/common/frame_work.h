// Test helper: one system's entry in a frame's FrameStats, by name (its work report included,
// penumbra/jobs/work_report.h). Throws std::runtime_error naming a system not in the frame.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "penumbra/jobs/executor.h"

namespace penumbra::test {

inline const jobs::SystemTiming& system_timing(const jobs::FrameStats& frame,
                                               std::string_view name) {
  for (const jobs::SystemTiming& t : frame.systems)
    if (t.name == name) return t;
  throw std::runtime_error("no system '" + std::string(name) + "' in the frame");
}

}  // namespace penumbra::test
