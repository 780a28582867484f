// The valley game's rules as pure functions on plain data (valley_game.h runs them as systems):
// usable, and tested, without the ECS or the renderer.
// Threading: pure functions.
#pragma once

#include <span>

#include <glm/vec2.hpp>

#include "penumbra/components/terrain.h"
#include "penumbra/game/game_input.h"
#include "penumbra/game/valley_game.h"

namespace penumbra::game {

// The ground's world height at world xy (bilinear between samples, clamped to the field), and
// its slope (d height / d x, d height / d y) by central differences one cell apart.
float ground_height(const components::Terrain& terrain, glm::vec2 xy);
glm::vec2 ground_slope(const components::Terrain& terrain, glm::vec2 xy);

// A round obstacle on the ground (a boulder's bounding circle).
struct Obstacle {
  glm::vec2 centre{0.0f};
  float radius = 0.0f;
};

// One step of the orb: pushed by the stick (`move` in the frame of `heading`: y forward),
// pulled downhill, slowed by drag; kept on the field and pushed out of obstacles (the inward
// part of its velocity removed, half of it bounced back). Returns true when it touched one.
// Non-finite input leaves the orb where it was, at rest.
bool step_orb(Orb& orb, const components::Terrain& terrain, const GameInput& input, float heading,
              float dt, const ValleyConfig& config, std::span<const Obstacle> obstacles);

// The phase after this step's buttons. new_round: the round (orb, beacons, ground, timer,
// score) starts over: Start on the title or an end screen, Restart while playing, paused or at
// an end screen. Pause toggles playing and paused.
struct PhaseChange {
  GamePhase phase = GamePhase::kTitle;
  bool new_round = false;
};
PhaseChange next_phase(GamePhase phase, const GameInput& input);

// Points for a beacon lit with `time_left` seconds to go, and the bonus for lighting the last.
int beacon_points(float time_left);
int win_bonus(float time_left);

// The sky's intensity with `time_left` of `time_limit` to go: 1 at the start (and on the title
// screen: time_left = time_limit), `night` at 0, geometric between, rounded to whole steps of
// the factor `dusk_step` (> 1).
float dusk_intensity(float time_left, float time_limit, float night, float dusk_step);

// The beacons' places: `count` points on a ring around the valley's centre (radii between
// ring_min and ring_max of its width), evenly spread in angle with a jitter from `seed`;
// the same for the same arguments on every platform (no <random> distributions).
std::vector<glm::vec2> beacon_sites(const components::Terrain& terrain, const ValleyConfig& config);

}  // namespace penumbra::game
