#include "penumbra/game/valley_autopilot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace penumbra::game {

GameInput autopilot_input(const AutopilotView& v, const ValleyConfig& c) {
  GameInput in;
  if (!v.state || !v.orb) return in;
  const GameState& g = *v.state;
  switch (g.phase) {
    case GamePhase::kTitle:
      if (v.frame == 20) in.buttons = kButtonStart;  // a moment on the title screen
      return in;
    case GamePhase::kPaused:
      if (v.frame % 15 == 0) in.buttons = kButtonPause;  // resume after a moment
      return in;
    case GamePhase::kWon:
    case GamePhase::kLost:
      return in;
    case GamePhase::kPlaying:
      break;
  }
  if (g.steps == 300) {  // pause once, to show it
    in.buttons = kButtonPause;
    return in;
  }
  if (g.steps >= 120 && g.steps < 136) in.buttons = kButtonDig;  // dig once: a crater, one brush

  const Beacon* target = nullptr;
  float best = std::numeric_limits<float>::infinity();
  for (const Beacon& b : v.beacons) {
    const float d = glm::distance(glm::vec2(b.position), v.orb->position);
    if (!b.lit && d < best) best = d, target = &b;
  }
  if (!target) return in;
  const glm::vec2 to = glm::vec2(target->position) - v.orb->position;
  const glm::vec2 dir = to / std::max(glm::length(to), 1e-3f);
  // Aim for the speed that still stops at the beacon, and steer the velocity towards it.
  const float top = c.orb_accel / c.orb_drag;
  const glm::vec2 want = dir * std::min(top, 1.5f * best);
  glm::vec2 push = (want - v.orb->velocity) / top * 3.0f;
  if (glm::length(push) > 1.0f) push = glm::normalize(push);
  const glm::vec2 fwd(std::cos(g.heading), std::sin(g.heading)), right(fwd.y, -fwd.x);
  in.move_x = quantize_axis(glm::dot(push, right));
  in.move_y = quantize_axis(glm::dot(push, fwd));
  // The camera turns after the beacon (positive turn: to the left).
  const float off = std::remainder(std::atan2(dir.y, dir.x) - g.heading, 6.2831853f);
  in.turn = quantize_axis(off * 2.0f);
  return in;
}

}  // namespace penumbra::game
