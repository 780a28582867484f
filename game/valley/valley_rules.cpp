#include "penumbra/game/valley_rules.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "../terrain_height.h"
#include "penumbra/data/finite.h"
#include "penumbra/data/height_field.h"
#include "random_bits.h"

namespace penumbra::game {
namespace {

using detail::mix_bits;
using detail::unit_float;

using data::finite;

// World xy of the field's corners (sample (0, 0) and (w - 1, h - 1)).
glm::vec2 field_min(const components::Terrain& t) {
  return glm::vec2(t.origin);
}
glm::vec2 field_max(const components::Terrain& t) {
  const data::HeightField& f = *t.heights;
  return glm::vec2(t.origin) + f.cell_size * glm::vec2(f.width - 1, f.height - 1);
}

}  // namespace

float ground_height(const components::Terrain& t, glm::vec2 xy) {
  if (!t.heights || t.heights->width < 2 || t.heights->height < 2) return t.origin.z;
  return terrain_height(t, finite(xy) ? xy : glm::vec2(t.origin));  // the demo's (terrain_height.h)
}

glm::vec2 ground_slope(const components::Terrain& t, glm::vec2 xy) {
  if (!t.heights) return glm::vec2(0.0f);
  const float d = t.heights->cell_size;
  return glm::vec2(
             ground_height(t, xy + glm::vec2(d, 0)) - ground_height(t, xy - glm::vec2(d, 0)),
             ground_height(t, xy + glm::vec2(0, d)) - ground_height(t, xy - glm::vec2(0, d))) /
         (2 * d);
}

bool step_orb(Orb& orb, const components::Terrain& terrain, const GameInput& input, float heading,
              float dt, const ValleyConfig& c, std::span<const Obstacle> obstacles) {
  if (!finite(orb.position) || !finite(orb.velocity) || !std::isfinite(heading) ||
      !std::isfinite(dt)) {
    if (!finite(orb.position)) orb.position = orb.start;
    orb.velocity = glm::vec2(0.0f);
    return false;
  }
  const glm::vec2 forward(std::cos(heading), std::sin(heading));
  const glm::vec2 right(forward.y, -forward.x);
  const glm::vec2 stick = input.move();
  const glm::vec2 push = c.orb_accel * (stick.x * right + stick.y * forward);
  const glm::vec2 accel =
      push - c.slope_pull * ground_slope(terrain, orb.position) - c.orb_drag * orb.velocity;
  orb.velocity += accel * dt;  // semi-implicit Euler: velocity first, then position
  orb.position += orb.velocity * dt;

  bool touched = false;
  for (const Obstacle& o : obstacles) {
    const glm::vec2 d = orb.position - o.centre;
    const float reach = o.radius + c.orb_radius, dist = glm::length(d);
    if (!(dist < reach)) continue;
    touched = true;
    const glm::vec2 n = dist > 1e-3f ? d / dist : glm::vec2(1.0f, 0.0f);
    orb.position = o.centre + n * reach;
    const float inward = glm::dot(orb.velocity, n);
    if (inward < 0) orb.velocity -= 1.5f * inward * n;  // restitution 0.5
  }
  if (terrain.heights) {  // the field's edge is a wall
    const glm::vec2 lo = field_min(terrain) + c.orb_radius, hi = field_max(terrain) - c.orb_radius;
    for (int k = 0; k < 2; ++k) {
      if (orb.position[k] < lo[k] || orb.position[k] > hi[k]) {
        orb.position[k] = std::clamp(orb.position[k], lo[k], std::max(lo[k], hi[k]));
        orb.velocity[k] = 0.0f;
      }
    }
  }
  return touched;
}

PhaseChange next_phase(GamePhase phase, const GameInput& in) {
  const bool start = in.held(kButtonStart), restart = in.held(kButtonRestart),
             pause = in.held(kButtonPause);
  switch (phase) {
    case GamePhase::kTitle:
      return start || restart ? PhaseChange{GamePhase::kPlaying, true} : PhaseChange{phase, false};
    case GamePhase::kPlaying:
      if (restart) return {GamePhase::kPlaying, true};
      return {pause ? GamePhase::kPaused : phase, false};
    case GamePhase::kPaused:
      if (restart) return {GamePhase::kPlaying, true};
      return {pause || start ? GamePhase::kPlaying : phase, false};
    case GamePhase::kWon:
    case GamePhase::kLost:
      return start || restart ? PhaseChange{GamePhase::kPlaying, true} : PhaseChange{phase, false};
  }
  return {phase, false};
}

int beacon_points(float time_left) {
  return 100 + static_cast<int>(std::floor(std::max(0.0f, time_left)));
}
int win_bonus(float time_left) {
  return 10 * static_cast<int>(std::floor(std::max(0.0f, time_left)));
}

float dusk_intensity(float time_left, float time_limit, float night, float dusk_step) {
  if (!(time_limit > 0) || !(night > 0) || !(dusk_step > 1)) return 1.0f;
  const float gone = 1.0f - std::clamp(time_left / time_limit, 0.0f, 1.0f);
  const float steps = std::round(gone * std::log(night) / -std::log(dusk_step));
  return std::pow(dusk_step, -steps);
}

std::vector<glm::vec2> beacon_sites(const components::Terrain& terrain, const ValleyConfig& c) {
  std::vector<glm::vec2> sites;
  if (!terrain.heights || c.beacons < 1) return sites;
  const glm::vec2 lo = field_min(terrain), hi = field_max(terrain);
  const glm::vec2 centre = 0.5f * (lo + hi);
  const float width = std::min(hi.x - lo.x, hi.y - lo.y);
  std::uint32_t s = mix_bits(c.seed ^ 0x9e3779b9U);
  for (int k = 0; k < c.beacons; ++k) {
    s = mix_bits(s + 1);
    const float jitter = unit_float(s) - 0.5f;
    s = mix_bits(s + 1);
    const float r =
        width * (c.beacon_ring_min + (c.beacon_ring_max - c.beacon_ring_min) * unit_float(s));
    const float a = 2 * std::numbers::pi_v<float> * (static_cast<float>(k) + 0.6f * jitter) /
                    static_cast<float>(c.beacons);
    sites.push_back(centre + r * glm::vec2(std::cos(a), std::sin(a)));
  }
  return sites;
}

}  // namespace penumbra::game
