// The valley game (issue 16; docs/game.md): dusk falls over the valley of the real elevation
// model; the player rolls a glowing orb (a spherical light that lights the terrain) to the
// beacons and lights each before the time runs out, past the rolling boulders (blockers that
// push the orb away), digging or raising the ground under the orb where the way is steep.
//
// The world is the terrain demo's (terrain_demo.h: the DEM, the HDR sky and its sun, the
// boulders, the probe-lit floaters) without the demo's circling light and boulders, automatic
// edits and orbiting camera; the game's systems take their place. Rules are systems on the job
// graph, one fixed step (FrameTime::dt) per frame, and read nothing but the simulation's own state
// and GameInput, so a recorded session (game_input.h) replays bit-identically on any thread count.
//
// Systems (add_valley_systems, after add_terrain_demo_systems' clock and boulders):
//   game_input   reads InputPlayback; writes GameInput (the recording's next step; without
//                a playback, whatever the window put there)
//   game_bodies  reads FrameTime, Terrain, Boulder, Orb, SphericalLight; writes GroundBody,
//                Transform (the
//                boulders roll downhill, the creatures wander: ground_bodies.h)
//   game_rules   reads FrameTime, GameInput, ValleyGround, GroundBody; writes GameState, Orb,
//                Beacon, SphericalLight, Terrain (phase changes, the orb's motion, beacons,
//                edits, restoring the ground on restart: valley_rules.h)
//   game_dusk    reads GameState, ValleyGround; writes EnvironmentLight, RenderSettings (the
//                sky's intensity: dusk_intensity)
//   game_camera  reads GameState, Orb, SphericalLight, Terrain; writes Camera (behind the orb)
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/ecs/world.h"
#include "penumbra/game/game_input.h"
#include "penumbra/game/terrain_demo.h"
#include "penumbra/game/valley_canyon.h"
#include "penumbra/jobs/schedule.h"

namespace penumbra::data {
struct HeightField;
}

namespace penumbra::game {

enum class GamePhase : std::uint8_t { kTitle, kPlaying, kPaused, kWon, kLost };
const char* phase_name(GamePhase phase);

struct ValleyConfig {
  int beacons = 7;
  float time_limit = 120.0f;  // seconds of dusk left at the start of a round
  std::uint32_t seed = 1;     // beacon placement
  // The orb: a spherical light resting on the ground. Sizes are the valley's (19 km across).
  float orb_radius = 120.0f;                    // metres: light and collision radius
  glm::vec3 orb_radiance{60.0f, 42.0f, 20.0f};  // W / (m^2 sr)
  float orb_accel = 1500.0f;                    // m/s^2 at full stick
  float orb_drag = 1.2f;                        // 1/s: top speed accel / drag
  float slope_pull = 900.0f;                    // m/s^2 per unit of slope, downhill
  float turn_speed = 1.8f;                      // rad/s at full turn
  // Beacons: unlit until the orb's centre comes within `reach`; then a spherical light.
  float beacon_reach = 450.0f;
  float beacon_radius = 90.0f;
  glm::vec3 beacon_radiance{25.0f, 45.0f, 70.0f};
  float beacon_ring_min = 0.15f, beacon_ring_max = 0.42f;  // of the valley's width from its centre
  // Digging and raising: one brush every `edit_interval` seconds while the button is held.
  float edit_interval = 0.5f;
  float edit_radius = 700.0f;   // metres
  float edit_strength = 90.0f;  // metres of depth or height per brush
  int max_edits = 40;           // per round: the ground is not a sculpting tool
  // Dusk: the sky's light (EnvironmentLight::intensity, and the sky drawn) falls from 1 to
  // `night` over the round, geometrically, in steps of `dusk_step` (2%: about one a second),
  // so the terrain is composed again once a step, not every frame.
  float night = 0.06f;
  float dusk_step = 1.02f;
  bool canyon = true;  // the gorge with arches and probes along it (valley_canyon.h)
  CanyonConfig canyon_shape{};
};

// Resource: the round. Scores are integers so that replays compare exactly.
struct GameState {
  GamePhase phase = GamePhase::kTitle;
  int score = 0;
  int beacons_lit = 0, beacons_total = 0;
  float time_left = 0;      // seconds
  float heading = 0;        // radians from +x: the camera's, and what `move` is relative to
  std::uint64_t steps = 0;  // simulation steps of this round while playing
  int rounds = 0;           // rounds started (restarts count)
  int edits = 0;            // brushes this round
  float edit_wait = 0;      // seconds until the next brush may come
  bool blocked = false;     // the orb touched a boulder this step
};

// Per orb (one): its motion on the ground; the entity also holds the SphericalLight.
struct Orb {
  glm::vec2 position{0.0f};  // world xy, metres (the light sits at the ground + radius)
  glm::vec2 velocity{0.0f};  // m/s
  glm::vec2 start{0.0f};
};

// Per beacon: where it stands; the entity also holds a SphericalLight, radius 0 until lit.
struct Beacon {
  glm::vec3 position{0.0f};  // world, the light's centre when lit
  bool lit = false;
};

// Resource: the valley as the round started (ground and sky brightness), restored on restart.
struct ValleyGround {
  std::shared_ptr<const data::HeightField> heights;
  float sky_intensity = 1.0f;  // RenderSettings::sky.environment_intensity at full daylight
};

// Resource: a recorded session being replayed; after its last step the input is empty.
struct InputPlayback {
  InputRecording recording;
  std::size_t next = 0;
};

// The terrain demo's world as the game uses it: `demo` without the circling light, the timed
// edits and the orbiting camera, with the game's systems (add_valley_systems(config)) before
// the lighting. Populate the world with it, then populate_valley.
TerrainDemoConfig valley_world(TerrainDemoConfig demo, const ValleyConfig& config = {});

// Adds the game's entities and resources to a world holding the terrain demo's (terrain_demo.h,
// populated with circling_light and orbit_camera off). Throws std::invalid_argument for a
// config the game cannot play (no terrain, beacons < 1, non-positive sizes), naming the field.
void populate_valley(ecs::World& world, const ValleyConfig& config = {});
void add_valley_systems(jobs::Schedule& schedule, const ValleyConfig& config = {});

}  // namespace penumbra::game
