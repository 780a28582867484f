#include "penumbra/game/sample_world.h"

#include <cmath>

#include "penumbra/components/frame_time.h"
#include "penumbra/components/motion.h"

namespace penumbra::game {
namespace {
using components::FrameTime;
using components::Lifetime;
using components::Position;
using components::Velocity;

constexpr float kHalfBox = 50.0f;

// Deterministic hash to [0, 1): particle placement must not depend on threads or call order.
float unit_hash(std::uint32_t a, std::uint32_t b) {
  std::uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u + (a << 6) + (a >> 2));
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

void spawn_values(std::uint32_t key, std::uint32_t salt, Position& p, Velocity& v, Lifetime& l) {
  p = {(unit_hash(key, salt) - 0.5f) * 2 * kHalfBox,
       (unit_hash(key, salt + 1) - 0.5f) * 2 * kHalfBox,
       (unit_hash(key, salt + 2) - 0.5f) * 2 * kHalfBox};
  v = {(unit_hash(key, salt + 3) - 0.5f) * 10, (unit_hash(key, salt + 4) - 0.5f) * 10,
       (unit_hash(key, salt + 5) - 0.5f) * 10};
  l = {1.0f + 9.0f * unit_hash(key, salt + 6)};
}
}  // namespace

void populate_sample_world(ecs::World& world, const SampleWorldConfig& config) {
  world.emplace_resource<FrameTime>();
  world.emplace_resource<Centroid>();
  SampleLights& lights = world.emplace_resource<SampleLights>();
  lights.count = config.lights < 16 ? config.lights : 16;
  for (std::size_t i = 0; i < lights.count; ++i) {
    const auto k = static_cast<std::uint32_t>(i);
    lights.lights[i] = {(unit_hash(k, config.seed) - 0.5f) * 80,
                        (unit_hash(k, config.seed + 1) - 0.5f) * 80,
                        (unit_hash(k, config.seed + 2) - 0.5f) * 80,
                        50 * unit_hash(k, 11),
                        50 * unit_hash(k, 12),
                        50 * unit_hash(k, 13)};
  }
  for (std::size_t i = 0; i < config.particles; ++i) {
    Position p;
    Velocity v;
    Lifetime l;
    spawn_values(static_cast<std::uint32_t>(i), config.seed * 16, p, v, l);
    world.create_with(p, v, l, Irradiance{});
  }
}

void add_sample_systems(jobs::Schedule& s) {
  s.add_task("clock", [](jobs::SystemContext& ctx) {
     FrameTime& t = ctx.world().resource<FrameTime>();
     t.elapsed += t.dt;
     ++t.frame;
   }).writes<FrameTime>();

  s.add_chunks<Position, const Velocity>(
       "integrate",
       [](jobs::SystemContext& ctx, const ecs::ChunkView<Position, const Velocity>& c) {
         const float dt = ctx.world().resource<const FrameTime>().dt;
         auto p = c.get<Position>();
         auto v = c.get<const Velocity>();
         for (std::size_t i = 0; i < c.size(); ++i) {
           p[i].x += v[i].x * dt;
           p[i].y += v[i].y * dt;
           p[i].z += v[i].z * dt;
         }
       })
      .reads<FrameTime>();

  s.add_each<const Position, Velocity>("bounce", [](const Position& p, Velocity& v) {
    if (std::fabs(p.x) > kHalfBox && p.x * v.x > 0) v.x = -v.x;
    if (std::fabs(p.y) > kHalfBox && p.y * v.y > 0) v.y = -v.y;
    if (std::fabs(p.z) > kHalfBox && p.z * v.z > 0) v.z = -v.z;
  });

  // Expired particles are destroyed and replaced by a fresh one (deferred commands).
  s.add_chunks<Lifetime>("age",
                         [](jobs::SystemContext& ctx, const ecs::ChunkView<Lifetime>& c) {
                           const FrameTime& t = ctx.world().resource<const FrameTime>();
                           auto life = c.get<Lifetime>();
                           const auto ents = c.entities();
                           for (std::size_t i = 0; i < c.size(); ++i) {
                             life[i].seconds -= t.dt;
                             if (life[i].seconds > 0) continue;
                             auto& cmd = ctx.commands();
                             cmd.destroy(ents[i]);
                             Position p;
                             Velocity v;
                             Lifetime l;
                             spawn_values(ents[i].index, static_cast<std::uint32_t>(t.frame) * 16u,
                                          p, v, l);
                             const ecs::Entity e = cmd.create();
                             cmd.add(e, p);
                             cmd.add(e, v);
                             cmd.add(e, l);
                             cmd.add(e, Irradiance{});
                           }
                         })
      .reads<FrameTime>()
      .spawns();

  s.add_reduce<Centroid, const Position>(
       "centroid", Centroid{},
       [](const ecs::ChunkView<const Position>& c, Centroid& acc) {
         for (const Position& p : c.get<const Position>()) {
           acc.x += p.x;
           acc.y += p.y;
           acc.z += p.z;
         }
         acc.count += c.size();
       },
       [](Centroid& a, const Centroid& b) {
         a.x += b.x;
         a.y += b.y;
         a.z += b.z;
         a.count += b.count;
       },
       [](jobs::SystemContext& ctx, Centroid& total) {
         const float inv = total.count > 0 ? 1.0f / static_cast<float>(total.count) : 0.0f;
         ctx.world().resource<Centroid>() = {total.x * inv, total.y * inv, total.z * inv,
                                             total.count};
       })
      .writes<Centroid>();

  s.add_chunks<const Position, Velocity>(
       "swirl",
       [](jobs::SystemContext& ctx, const ecs::ChunkView<const Position, Velocity>& c) {
         const Centroid& m = ctx.world().resource<const Centroid>();
         const float k = 0.05f * ctx.world().resource<const FrameTime>().dt;
         auto p = c.get<const Position>();
         auto v = c.get<Velocity>();
         for (std::size_t i = 0; i < c.size(); ++i) {
           v[i].x += (m.x - p[i].x) * k - (p[i].z - m.z) * k;
           v[i].z += (m.z - p[i].z) * k + (p[i].x - m.x) * k;
         }
       })
      .reads<Centroid, FrameTime>();

  s.add_task("move_lights",
             [](jobs::SystemContext& ctx) {
               SampleLights& l = ctx.world().resource<SampleLights>();
               const float a = ctx.world().resource<const FrameTime>().dt * 0.3f;
               const float ca = std::cos(a), sa = std::sin(a);
               for (std::size_t i = 0; i < l.count; ++i) {
                 const float x = l.lights[i].x, z = l.lights[i].z;
                 l.lights[i].x = ca * x - sa * z;
                 l.lights[i].z = sa * x + ca * z;
               }
             })
      .reads<FrameTime>()
      .writes<SampleLights>();

  // Inverse-square point lighting per particle: the compute-bound stand-in for a lighting pass.
  s.add_chunks<const Position, Irradiance>(
       "light",
       [](jobs::SystemContext& ctx, const ecs::ChunkView<const Position, Irradiance>& c) {
         const SampleLights& l = ctx.world().resource<const SampleLights>();
         auto p = c.get<const Position>();
         auto e = c.get<Irradiance>();
         for (std::size_t i = 0; i < c.size(); ++i) {
           Irradiance sum;
           for (std::size_t k = 0; k < l.count; ++k) {
             const float dx = l.lights[k].x - p[i].x, dy = l.lights[k].y - p[i].y,
                         dz = l.lights[k].z - p[i].z;
             const float inv = 1.0f / (dx * dx + dy * dy + dz * dz + 1.0f);
             sum.r += l.lights[k].r * inv;
             sum.g += l.lights[k].g * inv;
             sum.b += l.lights[k].b * inv;
           }
           e[i] = sum;
         }
       })
      .reads<SampleLights>();
}

}  // namespace penumbra::game
