#include "penumbra/systems/blocker_accumulation/blocker_systems.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "penumbra/components/camera.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/finite.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/blocker_accumulation/receiver_round_robin.h"
#include "penumbra/systems/blocker_accumulation/terrain_receivers.h"
#include "penumbra/systems/terrain_shadow/cast_shadow.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/terrain_horizons.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::blocker_accumulation {
namespace {

using components::EnvironmentLight;
using components::Receiver;
using components::ReceiverLighting;
using components::SphereSet;
using components::Transform;

constexpr int N = kSystemBands;
constexpr int kCastAzimuths = 16;  // the cast shadow's horizons per receiving entity
static_assert(N == ReceiverLighting::kBands);

std::string entity_name(ecs::Entity e) {
  return "entity " + std::to_string(e.index) + "v" + std::to_string(e.generation);
}

using data::finite;

sh::CoeffsRgb<N> environment_radiance(ecs::World& w) {
  sh::CoeffsRgb<N> radiance{};
  if (const EnvironmentLight* env = w.try_resource<const EnvironmentLight>())
    for (int c = 0; c < 3; ++c) {
      radiance[c] = sh::rotate_z<N>(env->radiance[c], env->rotation_z);
      for (float& v : radiance[c]) v *= env->intensity;
    }
  return radiance;
}

// A key light at the receivers: the world direction (the source's turned by the sky's
// rotation), its azimuth, angular radius and irradiance at normal incidence.
struct KeyLight {
  glm::vec3 direction;
  float phi, radius;
  glm::vec3 irradiance;
};

// The environment at the receivers: the SH of what is not a key light, and the key lights
// (BlockerSettingsResource::sources).
sh::CoeffsRgb<N> receiver_environment(ecs::World& w, std::vector<KeyLight>& keys) {
  keys.clear();
  const EnvironmentLight* env = w.try_resource<const EnvironmentLight>();
  if (!env) return {};
  const BlockerSettingsResource& s = w.resource<const BlockerSettingsResource>();
  const std::size_t mask = s.sources == components::EnvironmentSources::kKeyLights
                               ? components::key_light_mask(*env, s.key_light_max_radius)
                               : 0;
  const sh::CoeffsRgb<N>& sh = components::sh_without(*env, mask);
  sh::CoeffsRgb<N> radiance{};
  for (int c = 0; c < 3; ++c) {
    radiance[c] = sh::rotate_z<N>(sh[c], env->rotation_z);
    for (float& v : radiance[c]) v *= env->intensity;
  }
  for (std::size_t j = 0; j < env->sources.size(); ++j) {
    if (!(mask >> j & 1)) continue;
    const glm::vec3 dir = components::world_direction(env->sources[j], env->rotation_z);
    keys.push_back({dir, std::atan2(dir.y, dir.x), env->sources[j].angular_radius,
                    env->intensity * env->sources[j].irradiance});
  }
  return radiance;
}

// The share of each key light's disc above the terrain's horizon seen from `at` (world) in its
// azimuth (terrain_shadow::ray_horizon): per receiving entity at its origin, as its cast shadow
// is ([Giraud] sec. 4.1), not per point.
std::vector<float> key_light_terrain(std::span<const KeyLight> keys,
                                     const components::Terrain* terrain, const glm::vec3& at) {
  std::vector<float> share(keys.size(), 1.0f);
  if (!terrain) return share;
  const data::HeightField& f = *terrain->heights;
  const glm::vec3 q = at - terrain->origin;
  if (!(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z))) return share;
  for (std::size_t j = 0; j < keys.size(); ++j) {
    const float horizon = terrain_shadow::ray_horizon(
        f, terrain->height_scale, glm::vec2(q.x, q.y) / f.cell_size, q.z, keys[j].phi,
        std::numeric_limits<float>::infinity(), false);
    share[j] = terrain_shadow::disc_share_above(
        std::asin(std::clamp(keys[j].direction.z, -1.0f, 1.0f)) - horizon, keys[j].radius);
  }
  return share;
}

// The key lights' irradiance at (p, n): the disc the blockers leave times `terrain_share`.
glm::vec3 key_light_irradiance(const BlockerAccumulation<N>& acc, std::span<const KeyLight> keys,
                               std::span<const float> terrain_share, const glm::vec3& p,
                               const glm::vec3& n) {
  glm::vec3 e(0.0f);
  for (std::size_t j = 0; j < keys.size(); ++j) {
    const KeyLight& k = keys[j];
    const float c = glm::dot(n, k.direction);
    if (!(c > 0) || !(terrain_share[j] > 0)) continue;
    e += k.irradiance * (c * terrain_share[j] * acc.key_light_visibility(p, k.direction, k.radius));
  }
  return e;
}

// The bound and disc coverage of the set's spheres `members` (bound_group,
// blocker_accumulation.h); `bound`, when given, replaces the computed bound.
SetLayout::Group group_of(const std::vector<components::Sphere>& spheres,
                          const std::vector<std::uint32_t>& members, std::uint32_t first,
                          const components::Sphere* bound) {
  std::vector<WorldSphere> local(members.size());
  for (std::size_t i = 0; i < members.size(); ++i)
    local[i] = {spheres[members[i]].centre, spheres[members[i]].radius};
  const BlockerGroup g = bound_group(local);
  SetLayout::Group out{g.bound.centre, g.bound.radius, g.coverage, first,
                       static_cast<std::uint32_t>(members.size())};
  if (bound && members.size() > 1) {
    // Coverage of the given bound's disc: the computed one's, scaled by the discs' areas.
    out.centre = bound->centre;
    out.radius = std::max(bound->radius, g.bound.radius);
    const float k = g.bound.radius / std::max(out.radius, 1e-30f);
    out.coverage = std::clamp(g.coverage * k * k, 0.01f, 1.0f);
  }
  return out;
}

// [Ren06] hierarchy from the parent indices, or one group (SetLayout, blocker_systems.h).
SetLayout layout_of(const std::vector<components::Sphere>& spheres) {
  SetLayout layout;
  const std::size_t n = spheres.size();
  std::vector<std::int32_t> root(n, -1);
  bool hierarchy = false;
  for (std::size_t i = 0; i < n && layout.error.empty(); ++i) {
    std::int32_t at = static_cast<std::int32_t>(i);
    for (std::size_t steps = 0; spheres[static_cast<std::size_t>(at)].parent >= 0; ++steps) {
      const std::int32_t p = spheres[static_cast<std::size_t>(at)].parent;
      if (static_cast<std::size_t>(p) >= n || steps >= n) {
        layout.error = "sphere " + std::to_string(i) + ": parent " + std::to_string(p) +
                       (steps >= n ? " is in a cycle" : " is out of range");
        break;
      }
      at = p;
      hierarchy = true;
    }
    root[i] = at;
  }
  std::vector<std::uint32_t> all(n);
  for (std::uint32_t i = 0; i < n; ++i) all[i] = i;
  if (!hierarchy || !layout.error.empty()) {
    layout.leaves = all;
    layout.groups.push_back(group_of(spheres, all, 0, nullptr));
    return layout;
  }
  std::vector<bool> has_children(n, false);
  for (const components::Sphere& s : spheres)
    if (s.parent >= 0) has_children[static_cast<std::size_t>(s.parent)] = true;
  for (std::uint32_t r = 0; r < n; ++r) {
    if (spheres[r].parent >= 0) continue;
    std::vector<std::uint32_t> members;
    for (std::uint32_t i = 0; i < n; ++i)
      if (root[i] == static_cast<std::int32_t>(r) && !has_children[i]) members.push_back(i);
    const auto first = static_cast<std::uint32_t>(layout.leaves.size());
    layout.groups.push_back(group_of(spheres, members, first, &spheres[r]));
    layout.leaves.insert(layout.leaves.end(), members.begin(), members.end());
  }
  return layout;
}

void gather(ecs::World& w) {
  BlockerField& field = w.resource<BlockerField>();
  ++field.frame;
  const BlockerSettings& settings = w.resource<const BlockerSettingsResource>().settings;
  if (!field.accumulation || !(field.accumulation->settings() == settings))
    field.accumulation = std::make_shared<BlockerAccumulation<N>>(settings);
  field.errors.clear();
  std::vector<WorldSphere> spheres;
  std::vector<BlockerGroup> groups;
  std::erase_if(field.layouts, [](const auto& kv) { return kv.second.keep.use_count() <= 1; });
  w.query<const SphereSet, const Transform>().each([&](ecs::Entity e, const SphereSet& set,
                                                       const Transform& t) {
    if (!set.spheres) return;
    if (!finite(t.world)) {
      field.errors.push_back(entity_name(e) +
                             ": transform is not finite; its spheres are "
                             "left out");
      return;
    }
    auto [it, added] = field.layouts.try_emplace(set.spheres.get());
    if (added) {
      it->second = layout_of(*set.spheres);
      it->second.keep = set.spheres;
    }
    const SetLayout& layout = it->second;
    if (!layout.error.empty())
      field.errors.push_back(entity_name(e) + ": " + layout.error +
                             "; its spheres are used without the hierarchy");
    const glm::mat3 m(t.world);
    const float scale = std::max({glm::length(m[0]), glm::length(m[1]), glm::length(m[2])});
    const std::size_t first_sphere = spheres.size(), first_group = groups.size();
    for (const SetLayout::Group& g : layout.groups) {
      const std::size_t first = spheres.size();
      for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
        const components::Sphere& s = (*set.spheres)[layout.leaves[k]];
        const glm::vec3 c = glm::vec3(t.world * glm::vec4(s.centre, 1.0f));
        const float r = s.radius * scale;
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) ||
            !(std::isfinite(r) && r >= 0)) {
          field.errors.push_back(entity_name(e) + ": sphere " + std::to_string(layout.leaves[k]) +
                                 " is not finite or has a negative radius; its spheres are "
                                 "left out");
          spheres.resize(first_sphere);
          groups.resize(first_group);
          return;
        }
        spheres.push_back({c, r});
      }
      if (spheres.size() == first) continue;
      const glm::vec3 bc = glm::vec3(t.world * glm::vec4(g.centre, 1.0f));
      if (!std::isfinite(bc.x) || !std::isfinite(bc.y) || !std::isfinite(bc.z) ||
          !std::isfinite(g.radius * scale)) {
        field.errors.push_back(entity_name(e) +
                               ": a bounding sphere is not finite; its spheres are left out");
        spheres.resize(first_sphere);
        groups.resize(first_group);
        return;
      }
      groups.push_back({{bc, g.radius * scale},
                        static_cast<std::uint32_t>(first),
                        static_cast<std::uint32_t>(spheres.size() - first),
                        g.coverage});
    }
  });
  field.accumulation->set_blockers(std::move(spheres), std::move(groups));
  std::vector<LightSource> lights;
  w.query<const components::SphericalLight>().each([&](const components::SphericalLight& l) {
    if (std::isfinite(l.position.x) && std::isfinite(l.position.y) && std::isfinite(l.position.z) &&
        std::isfinite(l.radius) && l.radius > 0)
      lights.push_back({l.position, l.radius, l.radiance});
  });
  field.accumulation->set_lights(std::move(lights));
}

void shade(ecs::World& w) {
  BlockerField& field = w.resource<BlockerField>();
  if (!field.accumulation) return;
  const BlockerAccumulation<N>& acc = *field.accumulation;
  const auto* routing = w.try_resource<const components::LocalLightRouting>();
  const bool local_lights =  // else spherical_lights.gather gives them (ReceiverLighting::local)
      !routing || routing->path == components::LocalLightPath::kBlockerSh;
  std::vector<KeyLight> keys;
  const sh::CoeffsRgb<N> radiance = receiver_environment(w, keys);
  const components::Camera* camera = w.try_resource<const components::Camera>();
  field.receivers = 0;
  const components::Terrain* terrain = nullptr;
  w.query<const components::Terrain>().each([&](const components::Terrain& t) {
    if (!terrain && t.heights) terrain = &t;
  });
  if (terrain && !field.cast_wedges)
    field.cast_wedges = std::make_shared<terrain_shadow::LogWedge<N>>(
        kCastAzimuths, std::log(acc.settings().blocker.epsilon));
  // Which entities this frame: every new one, then round robin from the cursor while the
  // budget of points lasts (at least one entity per frame).
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
  const std::vector<Item> now = pick_receivers(
      all, w.resource<const BlockerSettingsResource>().receiver_budget, field.cursor,
      [](const Item& it) { return !it.out->irradiance; },
      [](const Item& it) { return it.r->points ? it.r->points->size() : std::size_t{0}; });
  jobs::report_work(now.size(), all.size() - now.size());  // not re-shaded this frame
  for (const Item& it : now) {
    [&](ecs::Entity e, const Receiver& r, const Transform& t, ReceiverLighting& out) {
      const std::vector<float> key_share = key_light_terrain(keys, terrain, glm::vec3(t.world[3]));
      std::optional<sh::Coeffs<N>> cast;
      if (terrain) {
        const glm::vec3 at = glm::vec3(t.world[3]) - terrain->origin;
        if (std::isfinite(at.x) && std::isfinite(at.y) && std::isfinite(at.z))
          cast = terrain_shadow::cast_shadow_log_visibility<N>(  // [Giraud] sec. 4.1
              *terrain->heights, terrain->height_scale, at, *field.cast_wedges);
      }
      if (!r.points || !r.normals || r.points->size() != r.normals->size()) {
        field.errors.push_back(entity_name(e) + ": receiver points and normals differ");
        return;
      }
      const std::size_t n = r.points->size();
      const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(t.world)));
      const components::Material* material = w.get<components::Material>(e);
      if (material && !(std::isfinite(material->phong_exponent) && material->phong_exponent >= 0 &&
                        std::isfinite(material->albedo.x) && std::isfinite(material->albedo.y) &&
                        std::isfinite(material->albedo.z))) {
        field.errors.push_back(entity_name(e) +
                               ": Material albedo or Phong exponent is not finite or the "
                               "exponent is negative; shaded white and Lambertian");
        material = nullptr;
      }
      const glm::vec3 albedo = material ? material->albedo : glm::vec3(1.0f);
      const PhongLobe<N>* lobe = nullptr;  // [Giraud] eq. 27, one per exponent
      if (material && material->phong_exponent > 0 && camera) {
        auto [slot, added] = field.lobes.try_emplace(material->phong_exponent);
        if (added) slot->second = BlockerAccumulation<N>::phong_lobe(material->phong_exponent);
        lobe = &slot->second;
      }
      auto visibility = std::make_shared<std::vector<ReceiverLighting::Visibility>>(n);
      auto irradiance = std::make_shared<std::vector<glm::vec3>>(n);
      auto shown = std::make_shared<std::vector<glm::vec3>>(n);  // radiance per unit albedo
      std::mutex error_mutex;
      std::string error;
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, n, 256),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
              const glm::vec3 p = glm::vec3(t.world * glm::vec4((*r.points)[i], 1.0f));
              glm::vec3 nn = normal_matrix * (*r.normals)[i];
              const float len = glm::length(nn);
              if (!(len > 0) || !std::isfinite(len) || !std::isfinite(p.x) || !std::isfinite(p.y) ||
                  !std::isfinite(p.z)) {
                std::lock_guard lock(error_mutex);
                error = entity_name(e) + ": receiver point " + std::to_string(i) +
                        " or its normal is not finite";
                return;
              }
              nn /= len;
              const sh::Coeffs<N>* extra = cast ? &*cast : nullptr;
              (*irradiance)[i] =
                  acc.irradiance(radiance, p, nn, &(*visibility)[i], extra, local_lights);
              (*shown)[i] =
                  lobe ? acc.glossy_radiance(radiance, p, nn, glm::normalize(camera->position - p),
                                             *lobe, extra)
                       : (*irradiance)[i] * std::numbers::inv_pi_v<float>;
              if (!keys.empty()) {  // diffuse only: the lobe's highlight of a sun is not drawn
                const glm::vec3 k = key_light_irradiance(acc, keys, key_share, p, nn);
                (*irradiance)[i] += k;
                (*shown)[i] += k * std::numbers::inv_pi_v<float>;
              }
            }
          });
      if (!error.empty()) {
        field.errors.push_back(error + "; its lighting is left as it was");
        return;
      }
      auto outgoing = std::make_shared<std::vector<glm::vec3>>(n);
      for (std::size_t i = 0; i < n; ++i) (*outgoing)[i] = albedo * (*shown)[i];
      if (components::VertexLighting* v = w.get_mut<components::VertexLighting>(e))
        v->rgb = std::move(shown);
      out.visibility = std::move(visibility);
      out.irradiance = std::move(irradiance);
      out.radiance = std::move(outgoing);
      field.receivers += n;
    }(it.e, *it.r, *it.t, *it.out);
  }
}

void shade_terrain(jobs::SystemContext& ctx) {
  ecs::World& w = ctx.world();
  const BlockerField& field = w.resource<const BlockerField>();
  if (!field.accumulation) return;
  const BlockerAccumulation<N>& acc = *field.accumulation;
  const sh::CoeffsRgb<N> radiance = environment_radiance(w);
  const float log_eps = std::log(acc.settings().blocker.epsilon);
  w.query<const components::Terrain, const terrain_shadow::TerrainHorizons,
          components::TerrainLighting>()
      .each([&](ecs::Entity e, const components::Terrain& terrain,
                const terrain_shadow::TerrainHorizons& h, components::TerrainLighting& lighting) {
        BlockerTerrainState* state = w.get_mut<BlockerTerrainState>(e);
        if (!state) {  // arrives at the next sync point
          ctx.commands().add(e, BlockerTerrainState{});
          return;
        }
        if (lighting.composed)  // the terrain system's own lighting, whatever ran after us
          state->base = lighting.composed;
        else if (lighting.rgb != state->published)
          state->base = lighting.rgb;  // republished by whoever wrote it
        if (!state->base || !terrain.heights || !h.horizons || !h.normals ||
            h.horizons->azimuths < 3)
          return;
        if (!state->wedges || state->wedges->azimuths() != h.horizons->azimuths ||
            state->wedges->log_eps() != log_eps)
          state->wedges =
              std::make_shared<terrain_shadow::LogWedge<N>>(h.horizons->azimuths, log_eps);
        const TerrainReceivers t{terrain.heights.get(), terrain.origin, terrain.height_scale,
                                 h.horizons.get(), h.normals.get()};
        const BlockerSettingsResource& settings = w.resource<const BlockerSettingsResource>();
        const int period = std::max(1, settings.refresh_period);
        const int stride = settings.terrain_sampling == TerrainSampling::kEverySecondTexel ? 2 : 1;
        const TerrainShadeStats stats = update_terrain_ratios<N>(
            t, acc, *state->wedges, radiance, state->ratio,
            static_cast<int>(field.frame % static_cast<std::uint64_t>(period)), period, stride);
        state->reached = stats.reached;
        bool any = false;
        for (const glm::vec3& q : state->ratio) any |= q != glm::vec3(1.0f);
        if (!any || state->base->size() != state->ratio.size()) {
          lighting.rgb = state->base;
          state->published = state->base;
          return;
        }
        auto shaded = std::make_shared<std::vector<glm::vec3>>(*state->base);
        for (std::size_t i = 0; i < shaded->size(); ++i) (*shaded)[i] *= state->ratio[i];
        lighting.rgb = shaded;
        state->published = std::move(shaded);
      });
}

}  // namespace

void emplace_blocker_resources(ecs::World& world, const BlockerSettings& settings) {
  if (!world.try_resource<BlockerSettingsResource>())
    world.emplace_resource<BlockerSettingsResource>(BlockerSettingsResource{settings});
  if (!world.try_resource<BlockerField>()) world.emplace_resource<BlockerField>();
}

void add_blocker_systems(jobs::Schedule& schedule) {
  schedule.add_task("blockers.gather", [](jobs::SystemContext& ctx) { gather(ctx.world()); })
      .reads<SphereSet, Transform, BlockerSettingsResource, components::SphericalLight>()
      .writes<BlockerField>();
  schedule.add_task("blockers.shade", [](jobs::SystemContext& ctx) { shade(ctx.world()); })
      .reads<Receiver, Transform, components::Material, components::Camera, EnvironmentLight,
             components::Terrain, BlockerSettingsResource, components::LocalLightRouting>()
      .writes<BlockerField, ReceiverLighting, components::VertexLighting>();
  schedule.add_task("blockers.terrain", shade_terrain)
      .reads<components::Terrain, terrain_shadow::TerrainHorizons, BlockerField, EnvironmentLight,
             BlockerSettingsResource>()
      .writes<components::TerrainLighting, BlockerTerrainState>()
      .structural<BlockerTerrainState>();
}

}  // namespace penumbra::blocker_accumulation
