// Real time in fixed simulation steps: how many steps a frame owes the wall clock, so that a
// game runs at the same speed at any frame rate while every step stays the same length (what
// makes a recorded session replay exactly). A slow machine slows the game rather than falling
// further behind each frame: at most `max_steps` a frame, the rest of the debt forgotten.
// Threading: a plain value; one thread.
#pragma once

#include <algorithm>

namespace penumbra::game {

class FixedStepClock {
 public:
  // Starts owing one step, so that the first frame has something to draw.
  explicit FixedStepClock(double step_seconds, int max_steps = 4)
      : step_(step_seconds), max_steps_(max_steps), owed_(step_seconds) {}

  // Steps to run for a frame `elapsed_seconds` after the previous one (0 when the frame came
  // early: draw the last step again).
  int steps(double elapsed_seconds) {
    owed_ += std::max(0.0, elapsed_seconds);
    int n = static_cast<int>(owed_ / step_);
    owed_ -= n * step_;
    if (n > max_steps_) n = max_steps_, owed_ = 0;
    return n;
  }

 private:
  double step_;
  int max_steps_;
  double owed_;
};

}  // namespace penumbra::game
