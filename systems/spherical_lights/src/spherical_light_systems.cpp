#include "penumbra/systems/spherical_lights/spherical_light_systems.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/reflector.h"
#include "penumbra/components/reflector_radiance.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/finite.h"
#include "penumbra/data/height_field.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/blocker_accumulation/receiver_round_robin.h"
#include "penumbra/systems/spherical_lights/terrain_indirect.h"
#include "penumbra/systems/terrain_shadow/cast_shadow.h"
#include "penumbra/systems/terrain_shadow/terrain_horizons.h"

namespace penumbra::spherical_lights {
namespace {

using components::EnvironmentLight;
using components::Receiver;
using components::ReceiverLighting;
using components::Reflector;
using components::ReflectorRadiance;
using components::Transform;

constexpr int N = kSystemBands;
constexpr int kCastAzimuths = 16;  // the terrain's cast shadow, as blockers.shade
static_assert(N == ReflectorRadiance::kBands && N == blocker_accumulation::kSystemBands);

std::string entity_name(ecs::Entity e) {
  return "entity " + std::to_string(e.index) + "v" + std::to_string(e.generation);
}

using data::finite;

// [Guerrero08] sec. 7.1: rigid motion and uniform scale (the largest axis scale, as
// blockers.gather scales radii).
bool pose_of(const glm::mat4& world, ObjectPose& pose) {
  const glm::mat3 m(world);
  const float sx = glm::length(m[0]), sy = glm::length(m[1]), sz = glm::length(m[2]);
  if (!(sx > 0 && sy > 0 && sz > 0)) return false;
  pose.rotation = glm::mat3(m[0] / sx, m[1] / sy, m[2] / sz);
  pose.scale = std::max({sx, sy, sz});
  pose.translation = glm::vec3(world[3]);
  return true;
}

sh::CoeffsRgb<N> environment_radiance(ecs::World& w) {
  sh::CoeffsRgb<N> radiance{};
  if (const EnvironmentLight* env = w.try_resource<const EnvironmentLight>()) {
    for (int c = 0; c < 3; ++c) {
      radiance[c] = sh::rotate_z<N>(env->radiance[c], env->rotation_z);
      for (float& v : radiance[c]) v *= env->intensity;
    }
  }
  return radiance;
}

// The local lights as spherical lights ([Guerrero08] sec. 4: a uniform sphere's radiance SH is
// its band-0 coefficient), shadowed by every blocker sphere of the frame, each object's spheres
// one object (for per-object blocking); null when the routing does not ask for it or there is
// no local light.
void update_local_gather(ecs::World& w, SphericalLightField& field,
                         const SphereLightSettings& settings,
                         const blocker_accumulation::BlockerField* blockers) {
  const auto* routing = w.try_resource<const components::LocalLightRouting>();
  field.local_lights = 0;
  if (!routing || routing->path != components::LocalLightPath::kSphereLightGather) {
    field.local_gather.reset();
    return;
  }
  std::vector<SphereLightSource<N>> sources;
  std::uint32_t object = 0;
  if (blockers && blockers->accumulation) {
    const auto spheres = blockers->accumulation->blockers();
    for (const blocker_accumulation::BlockerGroup& g : blockers->accumulation->groups()) {
      for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
        SphereLightSource<N> s;  // radiance zero: blocks only
        s.centre = spheres[k].centre;
        s.radius = spheres[k].radius;
        s.object = object;
        sources.push_back(s);
      }
      ++object;
    }
  }
  w.query<const components::SphericalLight>().each([&](const components::SphericalLight& l) {
    const bool finite = std::isfinite(l.position.x) && std::isfinite(l.position.y) &&
                        std::isfinite(l.position.z) && std::isfinite(l.radius) &&
                        std::isfinite(l.radiance.x) && std::isfinite(l.radiance.y) &&
                        std::isfinite(l.radiance.z);
    if (!finite || !(l.radius > 0)) return;  // as blockers.gather: radius 0 is no light
    SphereLightSource<N> s;
    s.centre = l.position;
    s.radius = l.radius;
    s.object = object++;
    for (int c = 0; c < 3; ++c)
      s.radiance[c][0] = l.radiance[c] * 2.0f * std::sqrt(std::numbers::pi_v<float>);  // Y_00
    s.blocks = false;  // a lamp shadows nothing ([Guerrero08] treats lights and blockers alike)
    sources.push_back(s);
    ++field.local_lights;
  });
  if (field.local_lights == 0) {
    field.local_gather.reset();
    return;
  }
  // A lamp is direct light: never cut off or faded by its size in the sky (min_sin 0, which
  // also lets every blocker sphere shadow it wherever it is).
  SphereLightSettings local = settings;
  local.blocker.min_sin = 0.0f;
  if (!field.local_gather || field.local_gather->settings() != local)
    field.local_gather = std::make_shared<SphereLightGather<N>>(local);
  field.local_gather->set_lights(std::move(sources));
}

void reflect(ecs::World& w) {
  SphericalLightField& field = w.resource<SphericalLightField>();
  const SphericalLightSettingsResource& settings =
      w.resource<const SphericalLightSettingsResource>();
  field.errors.clear();
  field.sample_points = 0;
  if (!field.gather || field.gather->settings() != settings.settings) {
    field.gather = std::make_shared<SphereLightGather<N>>(settings.settings);
  }
  SphereLightSettings terrain_settings = settings.settings;
  terrain_settings.horizon = settings.terrain_horizon;
  if (!field.terrain_gather || field.terrain_gather->settings() != terrain_settings) {
    field.terrain_gather = std::make_shared<SphereLightGather<N>>(terrain_settings);
  }
  const blocker_accumulation::BlockerField* blockers =
      w.try_resource<const blocker_accumulation::BlockerField>();
  update_local_gather(w, field, settings.settings, blockers);
  std::vector<SphereLightSource<N>> lights;
  if (settings.indirect && blockers && blockers->accumulation) {
    const sh::CoeffsRgb<N> environment = environment_radiance(w);
    const components::Terrain* terrain = nullptr;
    w.query<const components::Terrain>().each([&](const components::Terrain& t) {
      if (!terrain && t.heights) terrain = &t;
    });
    if (terrain && !field.cast_wedges) {
      field.cast_wedges = std::make_shared<const terrain_shadow::LogWedge<N>>(
          kCastAzimuths, std::log(blockers->accumulation->settings().blocker.epsilon));
    }
    // A sample point under the terrain's surface (bilinear between samples) reflects nothing.
    std::function<bool(const glm::vec3&)> buried;
    if (terrain) {
      buried = [terrain](const glm::vec3& p) {
        const data::HeightField& f = *terrain->heights;
        const float fx = (p.x - terrain->origin.x) / f.cell_size;
        const float fy = (p.y - terrain->origin.y) / f.cell_size;
        if (!(fx >= 0 && fy >= 0 && fx <= static_cast<float>(f.width - 1) &&
              fy <= static_cast<float>(f.height - 1)))
          return false;
        const int x = std::min(static_cast<int>(fx), f.width - 2);
        const int y = std::min(static_cast<int>(fy), f.height - 2);
        const float tx = fx - static_cast<float>(x), ty = fy - static_cast<float>(y);
        const float h = (1 - ty) * ((1 - tx) * f.at(x, y) + tx * f.at(x + 1, y)) +
                        ty * ((1 - tx) * f.at(x, y + 1) + tx * f.at(x + 1, y + 1));
        return p.z < terrain->origin.z + terrain->height_scale * h;
      };
    }
    std::uint32_t object = 0;
    w.query<const Reflector, const Transform, ReflectorRadiance>().each(
        [&](ecs::Entity e, const Reflector& r, const Transform& t, ReflectorRadiance& out) {
          ObjectPose pose;
          if (!r.samples || !finite(t.world) || !pose_of(t.world, pose)) {
            field.errors.push_back(entity_name(e) +
                                   ": no samples, or a transform that is not finite or has a "
                                   "zero scale; it emits no indirect light");
            return;
          }
          if (!field.lighting ||
              field.lighting->cells().cells() != static_cast<int>(r.samples->directions.size())) {
            field.lighting = std::make_shared<const ReflectorLighting<N>>(r.samples->directions);
          }
          const auto period = static_cast<std::uint64_t>(std::max(1, settings.reflect_period));
          const bool due = !out.radiance || out.radiance->size() != r.samples->lights.size() ||
                           (field.frame + e.index) % period == 0;
          jobs::report_item(due);
          if (due) {
            std::optional<sh::Coeffs<N>> cast;
            if (terrain) {
              cast = terrain_shadow::cast_shadow_log_visibility<N>(  // [Giraud] sec. 4.1
                  *terrain->heights, terrain->height_scale, pose.translation - terrain->origin,
                  *field.cast_wedges);
            }
            // [Guerrero08] sec. 5: direct light at the sample points, then L^c per light.
            out.radiance = std::make_shared<std::vector<sh::CoeffsRgb<N>>>(
                field.lighting->update(*r.samples, pose, *blockers->accumulation, environment,
                                       nullptr, cast ? &*cast : nullptr, buried));
            for (const auto& sl : r.samples->lights) field.sample_points += sl.count();
          }
          ReflectorLighting<N>::place(*r.samples, pose, *out.radiance, object++, lights);
        });
  }
  ++field.frame;
  field.lights = lights.size();
  field.terrain_gather->set_lights(lights);
  field.gather->set_lights(std::move(lights));
}

// [Guerrero08] eq. 14 at every point of one receiving entity (world space); zeros without a
// gather when the entity is beyond every light's reach. Null, with an error, for bad input.
std::shared_ptr<std::vector<glm::vec3>> gather_points(const SphereLightGather<N>& gather,
                                                      ecs::Entity e, const Receiver& r,
                                                      const glm::mat4& world,
                                                      std::vector<std::string>& errors) {
  const std::size_t n = r.points->size();
  // Beyond every light's reach: zeros, no gather (the bound of the points in world space).
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& q : *r.points) {
    const glm::vec3 p = glm::vec3(world * glm::vec4(q, 1.0f));
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  bool reached = false;
  const float min_sin = std::max(gather.settings().blocker.min_sin, 1e-3f);
  for (const SphereLightSource<N>& l : gather.lights()) {
    if (l.radiance[0][0] == 0 && l.radiance[1][0] == 0 && l.radiance[2][0] == 0) continue;
    const glm::vec3 nearest = glm::clamp(l.centre, lo, hi);
    reached = reached || glm::length(nearest - l.centre) < l.radius / min_sin;
  }
  auto out = std::make_shared<std::vector<glm::vec3>>(n, glm::vec3(0.0f));
  if (!reached) return out;
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
  std::mutex error_mutex;
  std::string error;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 128),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        const glm::vec3 p = glm::vec3(world * glm::vec4((*r.points)[i], 1.0f));
                        glm::vec3 nn = normal_matrix * (*r.normals)[i];
                        const float len = glm::length(nn);
                        if (!(len > 0) || !std::isfinite(len) || !std::isfinite(p.x) ||
                            !std::isfinite(p.y) || !std::isfinite(p.z)) {
                          std::lock_guard lock(error_mutex);
                          error = entity_name(e) + ": receiver point " + std::to_string(i) +
                                  " or its normal is not finite";
                          continue;
                        }
                        (*out)[i] = gather.irradiance(p, nn / len);  // [Guerrero08] eq. 14
                      }
                    });
  if (!error.empty()) errors.push_back(error + "; its light from spherical lights is left out");
  return out;
}

void gather(ecs::World& w) {
  SphericalLightField& field = w.resource<SphericalLightField>();
  const SphericalLightSettingsResource& settings =
      w.resource<const SphericalLightSettingsResource>();
  field.receivers = 0;
  const SphereLightGather<N>* indirect = settings.indirect ? field.gather.get() : nullptr;
  const SphereLightGather<N>* local = field.local_gather.get();
  if (!indirect) w.query<ReceiverLighting>().each([](ReceiverLighting& l) { l.indirect.reset(); });
  if (!local) w.query<ReceiverLighting>().each([](ReceiverLighting& l) { l.local.reset(); });
  if (!indirect && !local) return;
  struct Item {
    ecs::Entity e;
    const Receiver* r;
    const Transform* t;
    ReceiverLighting* out;
  };
  std::vector<Item> all;
  w.query<const Receiver, const Transform, ReceiverLighting>().each(
      [&](ecs::Entity e, const Receiver& r, const Transform& t, ReceiverLighting& out) {
        all.push_back({e, &r, &t, &out});
      });
  // Every entity missing a term now, then round robin within the point budget.
  const std::vector<Item> now = blocker_accumulation::pick_receivers(
      all, settings.receiver_budget, field.cursor,
      [&](const Item& it) { return (indirect && !it.out->indirect) || (local && !it.out->local); },
      [](const Item& it) { return it.r->points ? it.r->points->size() : std::size_t{0}; });
  jobs::report_work(now.size(), all.size() - now.size());  // not gathered again this frame
  for (const Item& it : now) {
    const Receiver& r = *it.r;
    if (!r.points || !r.normals || r.points->size() != r.normals->size() || !finite(it.t->world)) {
      field.errors.push_back(entity_name(it.e) +
                             ": receiver points and normals differ or the transform is not finite");
      continue;
    }
    if (indirect) it.out->indirect = gather_points(*indirect, it.e, r, it.t->world, field.errors);
    if (local) it.out->local = gather_points(*local, it.e, r, it.t->world, field.errors);
    field.receivers += r.points->size();
  }
}

void shade_terrain(jobs::SystemContext& ctx) {
  ecs::World& w = ctx.world();
  const SphericalLightField& field = w.resource<const SphericalLightField>();
  const SphericalLightSettingsResource& settings =
      w.resource<const SphericalLightSettingsResource>();
  w.query<const components::Terrain, const terrain_shadow::TerrainHorizons,
          components::TerrainLighting>()
      .each([&](ecs::Entity e, const components::Terrain& terrain,
                const terrain_shadow::TerrainHorizons& h, components::TerrainLighting& lighting) {
        SphericalLightTerrainState* state = w.get_mut<SphericalLightTerrainState>(e);
        if (!state) {  // arrives at the next sync point
          ctx.commands().add(e, SphericalLightTerrainState{});
          return;
        }
        // What the systems before us published this frame; our own array means nobody did.
        if (lighting.rgb != state->published) state->input = lighting.rgb;
        if (!state->input) return;
        const bool on = settings.indirect && field.terrain_gather &&
                        !field.terrain_gather->lights().empty() && terrain.heights && h.normals;
        if (on) {
          const blocker_accumulation::TerrainReceivers t{terrain.heights.get(), terrain.origin,
                                                         terrain.height_scale, nullptr,
                                                         h.normals.get()};
          const int period = std::max(1, settings.terrain_period);
          state->reached = update_terrain_indirect<N>(
              t, *field.terrain_gather, settings.terrain_min_sin, state->indirect,
              static_cast<int>(state->frame % static_cast<std::uint64_t>(period)), period);
        } else {
          state->reached = 0;
        }
        ++state->frame;
        if (state->reached == 0 || state->indirect.size() != state->input->size()) {
          state->indirect.clear();
          lighting.rgb = state->input;
          state->published = state->input;
          return;
        }
        auto out = std::make_shared<std::vector<glm::vec3>>(*state->input);
        for (std::size_t i = 0; i < out->size(); ++i) {
          (*out)[i] += state->indirect[i] * std::numbers::inv_pi_v<float>;  // [Guerrero08] eq. 12
        }
        lighting.rgb = out;
        state->published = std::move(out);
      });
}

}  // namespace

void emplace_spherical_light_resources(ecs::World& world, const SphereLightSettings& settings) {
  if (!world.try_resource<SphericalLightSettingsResource>()) {
    world.emplace_resource<SphericalLightSettingsResource>(
        SphericalLightSettingsResource{settings});
  }
  if (!world.try_resource<SphericalLightField>()) world.emplace_resource<SphericalLightField>();
}

void add_spherical_light_systems(jobs::Schedule& schedule) {
  schedule
      .add_task("spherical_lights.reflect", [](jobs::SystemContext& ctx) { reflect(ctx.world()); })
      .reads<Reflector, Transform, blocker_accumulation::BlockerField, EnvironmentLight,
             components::Terrain, SphericalLightSettingsResource, components::SphericalLight,
             components::LocalLightRouting>()
      .writes<ReflectorRadiance, SphericalLightField>();
  schedule
      .add_task("spherical_lights.gather", [](jobs::SystemContext& ctx) { gather(ctx.world()); })
      .reads<Receiver, Transform, SphericalLightSettingsResource>()
      .writes<SphericalLightField, ReceiverLighting>();  // local_gather: made by reflect
  schedule.add_task("spherical_lights.terrain", shade_terrain)
      .reads<components::Terrain, terrain_shadow::TerrainHorizons, SphericalLightField,
             SphericalLightSettingsResource>()
      .writes<components::TerrainLighting, SphericalLightTerrainState>()
      .structural<SphericalLightTerrainState>();
}

}  // namespace penumbra::spherical_lights
