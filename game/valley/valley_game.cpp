#include "penumbra/game/valley_game.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/game/boulders.h"
#include "penumbra/game/ground_bodies.h"
#include "penumbra/game/valley_rules.h"
#include "penumbra/systems/render_extract/render_extract.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"

namespace penumbra::game {
namespace {

using components::Camera;
using components::FrameTime;
using components::SphericalLight;
using components::Terrain;

const Terrain* find_terrain(ecs::World& w) {
  const Terrain* found = nullptr;
  w.query<const Terrain>().each([&](const Terrain& t) {
    if (!found && t.heights) found = &t;
  });
  return found;
}

float wrap_angle(float a) {
  return std::remainder(a, 2 * std::numbers::pi_v<float>);
}

// The orb's light centre: on the ground, one radius up.
glm::vec3 orb_centre(const Terrain& t, const Orb& orb, const ValleyConfig& c) {
  return glm::vec3(orb.position, ground_height(t, orb.position) + c.orb_radius);
}

// A new round: orb home and at rest, beacons dark, the ground as it was, timer and score reset.
void start_round(ecs::World& w, GameState& g, const ValleyConfig& c) {
  Terrain* terrain = nullptr;
  w.query<Terrain>().each([&](Terrain& t) {
    if (!terrain && t.heights) terrain = &t;
  });
  const ValleyGround* ground = w.try_resource<const ValleyGround>();
  if (terrain && ground && ground->heights && terrain->heights != ground->heights) {
    terrain->heights = ground->heights;
    ++terrain->version;
    terrain->edited = {0, 0, ground->heights->width, ground->heights->height};
  }
  w.query<Orb, SphericalLight>().each([&](Orb& orb, SphericalLight& light) {
    orb.position = orb.start;
    orb.velocity = glm::vec2(0.0f);
    if (terrain) light.position = orb_centre(*terrain, orb, c);
  });
  w.query<Beacon, SphericalLight>().each([&](Beacon& b, SphericalLight& light) {
    b.lit = false;
    light.position = b.position;
    light.radius = 0.0f;  // no light until lit
  });
  const std::uint64_t rounds = static_cast<std::uint64_t>(g.rounds) + 1;
  g = GameState{};
  g.rounds = static_cast<int>(rounds);
  g.phase = GamePhase::kPlaying;
  g.time_left = c.time_limit;
  w.query<const Beacon>().each([&](const Beacon&) { ++g.beacons_total; });
  // Facing the valley's centre from the start.
  w.query<const Orb>().each([&](const Orb& orb) {
    if (glm::length(orb.start) > 1.0f) g.heading = std::atan2(-orb.start.y, -orb.start.x);
  });
}

void rules(ecs::World& w, const ValleyConfig& c) {
  GameState& g = w.resource<GameState>();
  const GameInput in = w.resource<const GameInput>();
  const float dt = w.resource<const FrameTime>().dt;
  const PhaseChange change = next_phase(g.phase, in);
  if (change.new_round) start_round(w, g, c);
  g.phase = change.phase;
  if (g.phase != GamePhase::kPlaying) return;
  ++g.steps;
  g.heading = wrap_angle(g.heading + c.turn_speed * in.turn_rate() * dt);

  Terrain* terrain = nullptr;
  w.query<Terrain>().each([&](Terrain& t) {
    if (!terrain && t.heights) terrain = &t;
  });
  if (!terrain) return;
  std::vector<Obstacle> obstacles;
  w.query<const GroundBody>().each([&](const GroundBody& b) {
    obstacles.push_back({b.position, b.radius});
  });

  glm::vec3 orb_at(0.0f);
  bool have_orb = false;
  w.query<Orb, SphericalLight>().each([&](Orb& orb, SphericalLight& light) {
    g.blocked = step_orb(orb, *terrain, in, g.heading, dt, c, obstacles);
    light.position = orb_at = orb_centre(*terrain, orb, c);
    have_orb = true;
  });
  if (!have_orb) return;

  // Digging and raising under the orb: one brush per edit_interval while held.
  g.edit_wait = std::max(0.0f, g.edit_wait - dt);
  const bool dig = in.held(kButtonDig), raise = in.held(kButtonRaise);
  if ((dig != raise) && g.edit_wait <= 0.0f && g.edits < c.max_edits) {
    terrain_shadow::Brush b;
    b.kind = dig ? terrain_shadow::BrushKind::kCrater : terrain_shadow::BrushKind::kRaise;
    b.centre = glm::vec2(orb_at);
    b.radius = c.edit_radius;
    b.strength = c.edit_strength;
    if (terrain_shadow::apply_brush(*terrain, b)) ++g.edits;
    g.edit_wait = c.edit_interval;
  }

  // Beacons within reach light up.
  w.query<Beacon, SphericalLight>().each([&](Beacon& b, SphericalLight& light) {
    if (b.lit || !(glm::distance(glm::vec2(b.position), glm::vec2(orb_at)) <= c.beacon_reach))
      return;
    b.lit = true;
    light.radius = c.beacon_radius;
    light.radiance = c.beacon_radiance;
    ++g.beacons_lit;
    g.score += beacon_points(g.time_left);
  });

  g.time_left = std::max(0.0f, g.time_left - dt);
  if (g.beacons_total > 0 && g.beacons_lit == g.beacons_total) {
    g.score += win_bonus(g.time_left);
    g.phase = GamePhase::kWon;
  } else if (g.time_left <= 0.0f) {
    g.phase = GamePhase::kLost;
  }
}

// The boulders and creatures: their own motion, then contacts (with each other and the orb),
// then the Transforms the blocker system and the renderer read.
void move_bodies(ecs::World& w) {
  const Terrain* terrain = find_terrain(w);
  if (!terrain) return;
  const components::FrameTime& time = w.resource<const FrameTime>();
  std::vector<Obstacle> orbs;
  w.query<const Orb, const SphericalLight>().each([&](const Orb& o, const SphericalLight& l) {
    orbs.push_back({o.position, l.radius});
  });
  std::vector<GroundBody*> bodies;
  std::vector<GroundBody> moved;
  const BodyConfig config;
  w.query<GroundBody>().each([&](GroundBody& b) {
    step_body(b, *terrain, time.dt, time.frame, config);
    bodies.push_back(&b);
    moved.push_back(b);
  });
  separate_bodies(moved, orbs, *terrain);
  for (std::size_t i = 0; i < bodies.size(); ++i) *bodies[i] = moved[i];
  w.query<const GroundBody, const Boulder, components::Transform>().each(
      [&](const GroundBody& b, const Boulder& boulder, components::Transform& out) {
        out.world = body_transform(b, *terrain, boulder.scale, boulder.model_centre);
      });
}

// Behind the orb along the heading, looking a little ahead of it.
void follow(ecs::World& w) {
  const GameState& g = w.resource<const GameState>();
  const Terrain* terrain = find_terrain(w);
  Camera& cam = w.resource<Camera>();
  w.query<const Orb, const SphericalLight>().each([&](const Orb&, const SphericalLight& light) {
    const glm::vec3 fwd(std::cos(g.heading), std::sin(g.heading), 0.0f);
    // Far enough that a terrain texel (74 m) is a few pixels, near enough to see the orb.
    glm::vec3 eye = light.position - 5500.0f * fwd + glm::vec3(0, 0, 3800.0f);
    if (terrain) eye.z = std::max(eye.z, ground_height(*terrain, glm::vec2(eye)) + 400.0f);
    cam.position = eye;
    cam.target = light.position + 1200.0f * fwd;
    cam.vertical_fov = 0.75f;
    cam.near_plane = 10.0f;
    cam.far_plane = 60000.0f;
  });
}

// What the renderer shows of the orb and the beacons (wire spheres): the orb in its light's
// colour; a beacon dim until lit, then bright.
void markers(ecs::World& w, const ValleyConfig& c) {
  auto tone = [](glm::vec3 radiance, float gain) {
    return gain * radiance / std::max({radiance.x, radiance.y, radiance.z, 1e-6f});
  };
  w.query<const Orb, const SphericalLight, components::DebugSphere>().each(
      [&](const Orb&, const SphericalLight& l, components::DebugSphere& s) {
        s = {l.position, l.radius, tone(l.radiance, 6.0f)};
      });
  w.query<const Beacon, components::DebugSphere>().each(
      [&](const Beacon& b, components::DebugSphere& s) {
        s = {b.position, c.beacon_radius, tone(c.beacon_radiance, b.lit ? 6.0f : 0.6f)};
      });
}

// The sky dims as the round goes on (full daylight on the title screen).
void dusk(ecs::World& w, const ValleyConfig& c) {
  const GameState& g = w.resource<const GameState>();
  const float left = g.phase == GamePhase::kTitle ? c.time_limit : g.time_left;
  const float k = dusk_intensity(left, c.time_limit, c.night, c.dusk_step);
  if (auto* env = w.try_resource<components::EnvironmentLight>(); env && env->intensity != k)
    env->intensity = k;
  if (auto* rs = w.try_resource<systems::RenderSettings>())
    rs->sky.environment_intensity = k * w.resource<const ValleyGround>().sky_intensity;
}

void check(bool ok, const char* field) {
  if (!ok) throw std::invalid_argument(std::string("valley game config: ") + field);
}

}  // namespace

const char* phase_name(GamePhase p) {
  switch (p) {
    case GamePhase::kTitle:
      return "title";
    case GamePhase::kPlaying:
      return "playing";
    case GamePhase::kPaused:
      return "paused";
    case GamePhase::kWon:
      return "won";
    case GamePhase::kLost:
      return "lost";
  }
  return "?";
}

TerrainDemoConfig valley_world(TerrainDemoConfig demo, const ValleyConfig& config) {
  demo.circling_light = demo.orbit_camera = demo.circling_boulders = false;
  demo.edit_interval = 0;
  demo.gameplay = [config](jobs::Schedule& s) { add_valley_systems(s, config); };
  if (config.canyon) {
    const CanyonConfig canyon = config.canyon_shape;
    demo.shape_ground = [canyon](data::HeightField& f, glm::vec3 origin, float scale) {
      carve_canyon(f, origin, scale, canyon);
    };
    // The probes along its floor, about every probe_spacing of the terrain as populated.
    demo.probes.extra_probes = [canyon](const Terrain& t) {
      return canyon_probes(t.heights->cell_size * static_cast<float>(t.heights->width - 1), canyon);
    };
    // The arches occlude the canyon's probes and reflect their sandstone colour in the bake.
    demo.probes.bake_meshes = [canyon](const Terrain& t) {
      std::vector<BakeMesh> meshes;
      for (const ArchShape& a : canyon_arches(t, canyon))
        meshes.push_back({a.mesh, canyon.arch_albedo});
      return meshes;
    };
  }
  return demo;
}

void populate_valley(ecs::World& world, const ValleyConfig& c) {
  check(c.beacons >= 1 && c.beacons <= 64, "beacons must be in [1, 64]");
  check(c.time_limit > 0 && std::isfinite(c.time_limit), "time_limit must be > 0");
  check(c.orb_radius > 0 && c.beacon_radius > 0 && c.beacon_reach > 0 && c.edit_radius > 0,
        "orb_radius, beacon_radius, beacon_reach and edit_radius must be > 0");
  check(
      c.beacon_ring_min >= 0 && c.beacon_ring_min <= c.beacon_ring_max && c.beacon_ring_max < 0.5f,
      "beacon ring must satisfy 0 <= min <= max < 0.5");
  const Terrain* terrain = find_terrain(world);
  if (!terrain) throw std::invalid_argument("valley game: the world has no terrain with heights");
  const Terrain t = *terrain;  // the query's pointer does not outlive the entities added below

  world.emplace_resource<GameState>();
  world.emplace_resource<GameInput>();
  const auto* rs = world.try_resource<const systems::RenderSettings>();
  world.emplace_resource<ValleyGround>(
      ValleyGround{t.heights, rs ? rs->sky.environment_intensity : 1.0f});
  if (!world.try_resource<Camera>()) world.emplace_resource<Camera>();

  const data::HeightField& f = *t.heights;
  const glm::vec2 centre =
      glm::vec2(t.origin) + 0.5f * f.cell_size * glm::vec2(f.width - 1, f.height - 1);
  Orb orb;
  orb.start = orb.position = centre;
  world.create_with(orb, SphericalLight{orb_centre(t, orb, c), c.orb_radius, c.orb_radiance},
                    components::DebugSphere{});
  for (const glm::vec2 site : beacon_sites(t, c)) {
    const glm::vec3 at(site, ground_height(t, site) + 1.2f * c.beacon_radius);
    world.create_with(Beacon{at, false}, SphericalLight{at, 0.0f, c.beacon_radiance},
                      components::DebugSphere{});
  }
  world.resource<GameState>().beacons_total = c.beacons;

  if (c.canyon) add_canyon_arches(world, c.canyon_shape);

  // The demo's boulders as bodies on the ground: Suzannes roll, bunnies wander, starting where
  // the demo's circles put them at t = 0.
  std::vector<std::pair<ecs::Entity, GroundBody>> bodies;
  std::uint32_t id = 0;
  world.query<const Boulder, const components::MeshInstance>().each(
      [&](ecs::Entity e, const Boulder& b, const components::MeshInstance& mesh) {
        GroundBody body;
        body.motion = b.model == 1 ? BodyMotion::kRoll : BodyMotion::kWander;
        body.position = b.path_radius * glm::vec2(std::cos(b.phase), std::sin(b.phase));
        body.heading = b.phase + 0.5f * std::numbers::pi_v<float>;
        body.radius = b.radius;
        body.lift = b.radius;
        if (body.motion == BodyMotion::kWander && mesh.mesh && !mesh.mesh->positions.empty()) {
          float lowest = 0.0f;  // glTF y up: the feet are the lowest y
          for (const glm::vec3& p : mesh.mesh->positions)
            lowest = std::min(lowest, (p.y - b.model_centre.y) * b.scale);
          body.lift = -lowest;
        }
        body.id = ++id;
        bodies.emplace_back(e, body);
      });
  for (auto& [e, body] : bodies) world.add(e, body);
}

void add_valley_systems(jobs::Schedule& s, const ValleyConfig& config) {
  s.add_task("game_input", [](jobs::SystemContext& ctx) {
     ecs::World& w = ctx.world();
     InputPlayback* p = w.try_resource<InputPlayback>();
     if (!p) return;  // live input: the window wrote GameInput
     GameInput& in = w.resource<GameInput>();
     in = p->next < p->recording.steps.size() ? p->recording.steps[p->next] : GameInput{};
     ++p->next;
   }).writes<InputPlayback, GameInput>();
  s.add_task("game_bodies", [](jobs::SystemContext& ctx) { move_bodies(ctx.world()); })
      .reads<FrameTime, Terrain, Boulder, Orb, SphericalLight>()
      .writes<GroundBody, components::Transform>();
  s.add_task("game_rules", [config](jobs::SystemContext& ctx) { rules(ctx.world(), config); })
      .reads<FrameTime, GameInput, ValleyGround, GroundBody>()
      .writes<GameState, Orb, Beacon, SphericalLight, Terrain>();
  s.add_task("game_markers", [config](jobs::SystemContext& ctx) { markers(ctx.world(), config); })
      .reads<Orb, Beacon, SphericalLight>()
      .writes<components::DebugSphere>();
  s.add_task("game_dusk", [config](jobs::SystemContext& ctx) { dusk(ctx.world(), config); })
      .reads<GameState, ValleyGround>()
      .writes<components::EnvironmentLight, systems::RenderSettings>();
  s.add_task("game_camera", [](jobs::SystemContext& ctx) { follow(ctx.world()); })
      .reads<GameState, Orb, SphericalLight, Terrain>()
      .writes<Camera>();
}

}  // namespace penumbra::game
