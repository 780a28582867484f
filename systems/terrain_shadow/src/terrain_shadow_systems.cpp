#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/terrain_shadow/terrain_horizons.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_state.h"

namespace penumbra::terrain_shadow {
namespace {

using components::EnvironmentLight;
using components::SphericalLight;
using components::Terrain;
using components::TerrainLighting;

TerrainShadowState new_state(const TerrainShadowSettings& settings) {
  TerrainShadowState x;
  x.shadowing = std::make_shared<TerrainShadowing<kSystemBands>>(settings.config);
  x.refresh = LightRefresh(settings.light_refresh);
  x.environment_refresh = EnvironmentRefresh(settings.environment_refresh);
  return x;
}

// Brings x's visibility up to date with t; false when nothing changed.
bool update_visibility(TerrainShadowState& x, const Terrain& t) {
  if (x.field == t.heights.get() && x.version == t.version &&
      x.shadowing->height_scale() == t.height_scale)
    return false;
  const bool one_edit = x.field != nullptr && t.version == x.version + 1;
  x.last_update =
      one_edit ? x.shadowing->update_edit(t.heights, t.height_scale,
                                          {t.edited.x0, t.edited.y0, t.edited.x1, t.edited.y1})
               : x.shadowing->update(t.heights, t.height_scale);
  x.field = t.heights.get();
  x.version = t.version;
  ++x.visibility_stamp;
  return true;
}

void update_visibility(jobs::SystemContext& ctx) {
  ecs::World& w = ctx.world();
  const auto& settings = w.resource<const TerrainShadowSettings>();
  // State of terrains that went away (the entity is alive, its Terrain or heights are not).
  std::vector<ecs::Entity> gone;
  w.query<const TerrainShadowState>().each([&](ecs::Entity e, const TerrainShadowState&) {
    const Terrain* t = w.get<Terrain>(e);
    if (!t || !t->heights) gone.push_back(e);
  });
  for (ecs::Entity e : gone) {
    ctx.commands().remove<TerrainShadowState>(e);
    ctx.commands().remove<TerrainHorizons>(e);
  }
  w.query<const Terrain>().each([&](ecs::Entity e, const Terrain& t) {
    if (!t.heights) return;
    if (TerrainShadowState* x = w.get_mut<TerrainShadowState>(e)) {
      jobs::report_item(update_visibility(*x, t));  // skipped: the terrain did not change
      return;
    }
    // A new terrain: its state and what it publishes arrive with the next sync point, before
    // terrain_shadow.lights.
    TerrainShadowState x = new_state(settings);
    jobs::report_item(update_visibility(x, t));
    const auto& shadowing = x.shadowing;
    ctx.commands().add(e, TerrainHorizons{{shadowing, &shadowing->horizons()},
                                          {shadowing, &shadowing->normals()}});
    ctx.commands().add(e, std::move(x));
  });
}

bool same_light(const LightSample& a, const LightSample& b) {
  return a.centre == b.centre && a.radius == b.radius && a.radiance == b.radiance;
}

// The layers of `lights` (TerrainShadowState::LightLayer), in their order: kept for lights
// still there, new (never shaded) for new ones.
void match_layers(TerrainShadowState& x, const std::vector<ecs::Entity>& lights,
                  std::size_t tiles) {
  std::vector<TerrainShadowState::LightLayer> layers;
  layers.reserve(lights.size());
  for (ecs::Entity e : lights) {
    auto it = std::find_if(x.light_layers.begin(), x.light_layers.end(),
                           [&](const TerrainShadowState::LightLayer& l) { return l.entity == e; });
    if (it != x.light_layers.end() && it->tile_samples.size() == tiles) {
      layers.push_back(std::move(*it));
    } else {
      LightSample never;
      never.radius = -1.0f;
      layers.push_back({e, {}, std::vector<LightSample>(tiles, never)});
    }
  }
  x.light_layers = std::move(layers);
}

void update_lights(ecs::World& w) {
  std::vector<SphericalLight> lights;
  std::vector<ecs::Entity> entities;
  w.query<const SphericalLight>().each([&](ecs::Entity e, const SphericalLight& l) {
    lights.push_back(l);
    entities.push_back(e);
  });
  std::vector<LightSample> samples;
  std::vector<TexelRect> redo;
  w.query<const Terrain, TerrainShadowState>().each([&](const Terrain& terrain,
                                                        TerrainShadowState& x) {
    const Terrain* t = &terrain;
    if (!x.shadowing->ready()) return;
    const data::HeightField& f = x.shadowing->field();
    const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
    if (x.refresh_visibility != x.visibility_stamp || x.refresh_origin != t->origin) {
      // New terrain or an edit: every tile again (keeping the old values until it comes).
      std::vector<glm::vec3> positions(n);
      for (int y = 0; y < f.height; ++y)
        for (int xx = 0; xx < f.width; ++xx)
          positions[static_cast<std::size_t>(y) * f.width + xx] = x.shadowing->position(xx, y);
      x.refresh.reset(f.width, f.height, positions);
      x.refresh_visibility = x.visibility_stamp;
      x.refresh_origin = t->origin;
      x.light_layers.clear();
      if (x.light_irradiance.size() != n) x.light_irradiance.assign(n, glm::vec3(0.0f));
    }
    samples.clear();
    for (const SphericalLight& l : lights)
      samples.push_back({l.position - t->origin, l.radius, l.radiance});
    const std::vector<TexelRect>& tiles = x.refresh.plan(samples);
    jobs::report_work(tiles.size(), x.refresh.stats().tiles - tiles.size());  // tiles not re-shaded
    if (tiles.empty()) return;
    x.refresh.keep_previous(x.light_irradiance);
    const int tile = x.refresh.config().tile, tiles_x = (f.width + tile - 1) / tile;
    const std::size_t tile_count =
        static_cast<std::size_t>(tiles_x) * ((f.height + tile - 1) / tile);
    auto tile_index = [&](const TexelRect& r) {
      return static_cast<std::size_t>(r.y0 / tile) * tiles_x + r.x0 / tile;
    };
    match_layers(x, entities, tile_count);
    x.light_tile_shades = 0;
    for (std::size_t k = 0; k < samples.size(); ++k) {
      TerrainShadowState::LightLayer& layer = x.light_layers[k];
      redo.clear();
      for (const TexelRect& r : tiles) {
        LightSample& was = layer.tile_samples[tile_index(r)];
        if (same_light(was, samples[k])) continue;  // this light did not change here
        was = samples[k];
        redo.push_back(r);
      }
      if (redo.empty()) continue;
      x.light_tile_shades += redo.size();
      if (layer.irradiance.size() != n) layer.irradiance.assign(n, glm::vec3(0.0f));
      for (const TexelRect& r : redo)
        for (int y = r.y0; y < r.y1; ++y)
          std::fill_n(layer.irradiance.begin() + static_cast<std::ptrdiff_t>(y) * f.width + r.x0,
                      r.width(), glm::vec3(0.0f));
      const LightSample& l = samples[k];
      if (l.radius > 0)
        x.shadowing->add_spherical_light(l.centre, l.radius, l.radiance, layer.irradiance, redo);
    }
    // The tiles' sums, in light order from zero (as shading them together adds them).
    tbb::parallel_for(std::size_t{0}, tiles.size(), [&](std::size_t i) {
      const TexelRect& r = tiles[i];
      for (int y = r.y0; y < r.y1; ++y)
        for (int xx = r.x0; xx < r.x1; ++xx) {
          const std::size_t j = static_cast<std::size_t>(y) * f.width + xx;
          glm::vec3 sum(0.0f);
          for (const TerrainShadowState::LightLayer& layer : x.light_layers)
            if (!layer.irradiance.empty()) sum += layer.irradiance[j];
          x.light_irradiance[j] = sum;
        }
    });
    x.refresh.commit(&x.light_irradiance);
    x.lights_dirty.insert(x.lights_dirty.end(), tiles.begin(), tiles.end());  // for compose
    ++x.lights_stamp;
  });
}

// Which of the environment's sources stand apart as key lights (bit j: source j).
std::size_t key_light_mask(const EnvironmentLight* env, const TerrainShadowSettings& settings) {
  if (!env || settings.sources != EnvironmentSources::kKeyLights) return 0;
  return components::key_light_mask(*env, settings.key_light_max_radius);
}

// The key lights' poses; their horizons swept again where the light moved by more than
// settings.key_light_step of its radius or the terrain changed (then the generation is bumped).
void update_key_lights(const EnvironmentLight& env, const TerrainShadowSettings& settings,
                       std::size_t mask, TerrainShadowState& x, EnvironmentPose& pose) {
  x.key_lights.resize(env.sources.size());
  for (std::size_t j = 0; j < env.sources.size(); ++j) {
    if (!(mask >> j & 1)) continue;
    const components::EnvironmentSource& src = env.sources[j];
    const glm::vec3 dir = components::world_direction(src, env.rotation_z);
    const float phi = std::atan2(dir.y, dir.x);
    TerrainShadowState::KeyLight& k = x.key_lights[j];
    float moved = std::abs(std::remainder(phi - k.phi, 2 * std::numbers::pi_v<float>));
    moved *= std::sqrt(std::max(0.0f, 1 - dir.z * dir.z));  // on the sky, not in azimuth alone
    if (k.visibility != x.visibility_stamp || k.horizons.empty() ||
        !(moved <= settings.key_light_step * src.angular_radius)) {
      x.shadowing->key_light_horizons(dir, k.horizons);
      k.phi = phi;
      k.visibility = x.visibility_stamp;
      ++x.key_horizons_generation;
    }
    const float luminance =
        0.2126f * src.irradiance.x + 0.7152f * src.irradiance.y + 0.0722f * src.irradiance.z;
    pose.keys.push_back({dir, src.angular_radius, luminance, k.horizons});
    x.key_sources.push_back(j);
  }
  pose.horizons_generation = x.key_horizons_generation;
}

std::vector<float> transfer_norms(const TerrainShadowing<kSystemBands>& shadowing) {
  std::vector<float> norms(shadowing.transfer().size());
  for (std::size_t i = 0; i < norms.size(); ++i) {
    float s = 0;
    for (float c : shadowing.transfer()[i]) s += c * c;
    norms[i] = std::sqrt(s);
  }
  return norms;
}

// (intensity (E_env + E_key) + E_lights) / pi over the texels of `rects` ([Meier13] eq. 4.30;
// intensity: EnvironmentLight::intensity).
void compose_rects(TerrainShadowState& x, std::span<const TexelRect> rects, float intensity) {
  const bool lit = x.light_irradiance.size() == x.environment_irradiance.size();
  const int w = x.shadowing->field().width;
  tbb::parallel_for(std::size_t{0}, rects.size(), [&](std::size_t k) {
    const TexelRect& r = rects[k];
    for (int y = r.y0; y < r.y1; ++y)
      for (int xx = r.x0; xx < r.x1; ++xx) {
        const std::size_t i = static_cast<std::size_t>(y) * w + xx;
        const glm::vec3 e = intensity * x.environment_irradiance[i] +
                            (lit ? x.light_irradiance[i] : glm::vec3(0.0f));
        x.composed[i] = glm::max(e, glm::vec3(0.0f)) * std::numbers::inv_pi_v<float>;
      }
  });
}

void compose(ecs::World& w) {
  const EnvironmentLight* env = w.try_resource<const EnvironmentLight>();
  const auto& settings = w.resource<const TerrainShadowSettings>();
  const std::size_t keys = key_light_mask(env, settings);
  w.query<TerrainShadowState, TerrainLighting>().each([&](TerrainShadowState& x,
                                                          TerrainLighting& lighting) {
    TerrainLighting* out = &lighting;
    if (!x.shadowing->ready()) return;
    const data::HeightField& f = x.shadowing->field();
    const std::size_t n = static_cast<std::size_t>(f.width) * f.height;
    const std::uint64_t env_version = env ? env->version + 1 : 0;
    const std::uint64_t sources = keys ? ((env->sources_version + 1) << 8) | keys : 0;
    const float rotation = env ? env->rotation_z : 0.0f;
    const float intensity = env && env->intensity >= 0 ? env->intensity : 1.0f;
    // A new transfer, map or set of key lights: every tile now. A turned map (and its key
    // lights): the tiles where the turn can show, within a budget (environment_refresh.h).
    const bool whole = x.composed_visibility != x.visibility_stamp ||
                       x.composed_environment != env_version || x.composed_sources != sources ||
                       x.environment_irradiance.size() != n;
    if (x.composed_visibility != x.visibility_stamp || x.environment_irradiance.size() != n)
      x.environment_refresh.reset(f.width, f.height, transfer_norms(*x.shadowing));
    else if (whole)
      x.environment_refresh.invalidate();
    sh::CoeffsRgb<kSystemBands> radiance{};
    if (env)
      for (int c = 0; c < 3; ++c) {  // without the key lights: their OEM ([Ambrosj16] sec. 4.2)
        const auto& full = components::sh_without(*env, keys)[c];
        sh::Coeffs<kSystemBands> low{};  // the first kSystemBands bands of the map's SH
        std::copy_n(full.begin(), low.size(), low.begin());
        radiance[c] = sh::rotate_z<kSystemBands>(low, rotation);
      }
    EnvironmentPose pose;
    pose.rotation = rotation;
    pose.rotation_speed = rotation_speed_bound(radiance[0], radiance[1], radiance[2]);
    x.key_sources.clear();
    if (keys) update_key_lights(*env, settings, keys, x, pose);
    const std::vector<TexelRect>& tiles = x.environment_refresh.plan(pose, whole);
    const bool lights_changed = x.composed_lights != x.lights_stamp;
    const bool dimmed = x.composed_intensity != intensity;  // every texel, but only composed again
    if (tiles.empty() && !lights_changed && !dimmed)
      return jobs::report_item(false);  // nothing it reads changed visibly
    jobs::report_item(true);
    if (!tiles.empty()) {
      x.environment_irradiance.resize(n);
      x.shadowing->shade_environment(radiance, x.environment_irradiance, tiles);  // eq. 4.21
      for (std::size_t k = 0; k < pose.keys.size(); ++k) {
        const components::EnvironmentSource& src = env->sources[x.key_sources[k]];
        x.shadowing->add_key_light(pose.keys[k].direction, src.angular_radius, src.irradiance,
                                   pose.keys[k].horizons, x.environment_irradiance, tiles);
      }
      x.environment_refresh.commit(pose, x.shadowing->normals());
    }
    if (x.composed.size() != n || whole || dimmed) {
      x.composed.resize(n);
      const TexelRect all = TexelRect::all(f);
      compose_rects(x, {&all, 1}, intensity);
    } else {
      compose_rects(x, tiles, intensity);
      compose_rects(x, x.lights_dirty, intensity);
    }
    x.lights_dirty.clear();
    auto rgb = std::make_shared<std::vector<glm::vec3>>(x.composed);
    x.refresh.set_reference(*rgb, std::numbers::pi_v<float>);  // what the lights compare against
    x.environment_refresh.set_reference(*rgb, std::numbers::pi_v<float>);
    out->rgb = rgb;
    out->composed = std::move(rgb);
    out->width = f.width;
    out->height = f.height;
    x.composed_visibility = x.visibility_stamp;
    x.composed_lights = x.lights_stamp;
    x.composed_environment = env_version;
    x.composed_rotation = rotation;
    x.composed_intensity = intensity;
    x.composed_sources = sources;
  });
}

}  // namespace

void emplace_terrain_shadow_resources(ecs::World& world, const TerrainShadowConfig& config,
                                      const LightRefreshConfig& light_refresh) {
  if (world.try_resource<TerrainShadowSettings>()) return;
  TerrainShadowSettings settings;
  settings.config = config;
  settings.light_refresh = light_refresh;
  world.emplace_resource<TerrainShadowSettings>(settings);
}

void add_terrain_shadow_systems(jobs::Schedule& schedule) {
  schedule
      .add_task("terrain_shadow.visibility",
                [](jobs::SystemContext& ctx) { update_visibility(ctx); })
      .reads<Terrain, TerrainShadowSettings>()
      .writes<TerrainShadowState, TerrainHorizons>()
      .structural<TerrainShadowState, TerrainHorizons>();
  schedule
      .add_task("terrain_shadow.lights",
                [](jobs::SystemContext& ctx) { update_lights(ctx.world()); })
      .reads<SphericalLight, Terrain>()
      .writes<TerrainShadowState>();
  schedule
      .add_task("terrain_shadow.compose", [](jobs::SystemContext& ctx) { compose(ctx.world()); })
      .reads<EnvironmentLight, TerrainShadowSettings>()
      .writes<TerrainShadowState, TerrainLighting>();
}

}  // namespace penumbra::terrain_shadow
