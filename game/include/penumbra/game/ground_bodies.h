// The valley game's moving blockers (valley_game.h): the demo's boulders (boulders.h) as bodies
// on the ground. Suzannes roll down the slopes and, once at rest in a hollow, start again from a
// ridge; bunnies wander as creatures, turning away from steep climbs and the valley's edge.
// Both push each other and the orb's obstacles apart. Pure functions on plain data; the
// game_bodies system runs them and writes the Transforms the blocker system reads.
// Threading: pure functions.
#pragma once

#include <cstdint>
#include <span>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "penumbra/components/terrain.h"
#include "penumbra/game/valley_rules.h"

namespace penumbra::game {

enum class BodyMotion : std::uint8_t { kRoll, kWander };

// Per boulder entity (beside Boulder and Transform).
struct GroundBody {
  BodyMotion motion = BodyMotion::kRoll;
  glm::vec2 position{0.0f};                  // world xy, metres
  glm::vec2 velocity{0.0f};                  // m/s
  glm::quat tumble{1.0f, 0.0f, 0.0f, 0.0f};  // rolling: turned so far, without slipping
  float heading = 0.0f;                      // wandering: facing, radians from +x
  float radius = 0.0f;                       // on the ground (the sphere set's bounding radius)
  float lift = 0.0f;                         // the model's centre above the ground
  std::uint32_t id = 0;                      // its own random stream (turns, where it starts again)
  float rest = 0.0f;                         // rolling: seconds nearly still
  std::uint32_t restarts = 0;
};

struct BodyConfig {
  float roll_drag = 0.35f;      // 1/s
  float slope_pull = 900.0f;    // m/s^2 per unit of slope (as the orb's)
  float rest_speed = 40.0f;     // m/s: below it a roller is at rest...
  float rest_time = 5.0f;       // ...and after this long starts again from a ridge
  float wander_speed = 220.0f;  // m/s
  float wander_turn = 0.9f;     // rad/s at most
  float steep = 0.35f;          // a wanderer turns away from climbs steeper than this
};

// One step of a body's own motion (no contacts); `step` is the simulation step count (the
// wanderers' turns change every two seconds from it and their id).
void step_body(GroundBody& body, const components::Terrain& terrain, float dt, std::uint64_t step,
               const BodyConfig& config);
// Pushes overlapping bodies apart (equal shares, the inward parts of their velocities bounced
// with restitution 0.5) and out of the fixed obstacles (the orb), and keeps them on the field:
// four relaxation passes, each ending with the fixed obstacles and the field (exact there).
void separate_bodies(std::span<GroundBody> bodies, std::span<const Obstacle> fixed,
                     const components::Terrain& terrain);
// Model -> world: on the ground at its place, tumbled (rolling) or upright facing its heading
// (wandering; glTF models are y-up), scaled, about the model's centre.
glm::mat4 body_transform(const GroundBody& body, const components::Terrain& terrain, float scale,
                         const glm::vec3& model_centre);

}  // namespace penumbra::game
