#include "penumbra/game/probe_demo.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "penumbra/assets/gltf.h"
#include "penumbra/assets/mesh_simplify.h"
#include "penumbra/assets/sphere_fit.h"  // merge_instances
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/probe_anchor.h"
#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/components/probe_lighting.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/data/probe_cloud.h"
#include "penumbra/game/probe_sky_bake.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/convolution.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_systems.h"
#include "terrain_height.h"

namespace penumbra::game {

// The baked SH per sky step (probe_sky_bake.h) and what a step that is still missing needs.
struct ProbeSkyBake::Data {
  int w = 0;                              // sky steps around (2 pi / w each)
  std::vector<std::vector<float>> steps;  // per step: the cloud's SH; empty: not baked yet
  data::ProbeCloud cloud;                 // positions, cells, transforms; sh of the step shown
  data::HeightField field;                // heights as baked (the demo's vertical scale)
  std::shared_ptr<const data::EnvironmentMap> map;
  ProbeSkyBakeInputs inputs;  // points into field and map
  std::filesystem::path cache_dir;
};

namespace {

using components::DebugLine;
using components::DebugLines;
using components::EnvironmentLight;
using components::FrameTime;
using components::ProbeAnchor;
using components::ProbeCloudResource;
using components::ProbeLighting;
using components::Terrain;
using components::Transform;
using components::VertexLighting;

constexpr int kCloudBands = 3;  // the cloud's ([Cupisz12]; data::kProbeDefaultBands)

int sky_shift(float rotation, int w) {
  const float step = 2 * std::numbers::pi_v<float> / static_cast<float>(w);
  const long s = std::lround(rotation / step);
  return static_cast<int>(((s % w) + w) % w);
}

// The cloud with step `shift`'s SH, baking the step first if it is missing (a sky that turns
// when populate_probe_demo was told it would not).
std::shared_ptr<const data::ProbeCloud> cloud_with_sh(ProbeSkyBake& bake, int shift) {
  ProbeSkyBake::Data& d = *bake.data;
  std::vector<float>& sh = d.steps[static_cast<std::size_t>(shift)];
  if (sh.empty()) {
    const int which[] = {shift};
    ProbeSkySteps r = bake_probe_sky_steps(d.inputs, d.cloud, d.cache_dir, which);
    sh = std::move(r.sh[static_cast<std::size_t>(shift)]);
    bake.steps_baked += r.baked;
    bake.steps_loaded += r.loaded;
    for (std::string& n : r.notes) bake.notes.push_back(std::move(n));
  }
  auto cloud = std::make_shared<data::ProbeCloud>(d.cloud);
  cloud->sh = sh;
  return cloud;
}

const Terrain* find_terrain(ecs::World& w) {
  const Terrain* terrain = nullptr;
  w.query<const Terrain>().each([&](const Terrain& x) {
    if (!terrain && x.heights) terrain = &x;
  });
  return terrain;
}

void float_along(ecs::World& w) {
  const float t = static_cast<float>(w.resource<const FrameTime>().elapsed);
  const Terrain* terrain = find_terrain(w);
  w.query<const ProbeFloater, Transform>().each([&](const ProbeFloater& f, Transform& out) {
    const float a = f.phase + f.speed * t / f.path_radius;
    const glm::vec2 xy = f.path_radius * glm::vec2(std::cos(a), std::sin(a));
    // The highest ground under the object (centre and four points at its radius), so that it
    // clears the hills it crosses.
    float ground = 0;
    if (terrain) {
      ground = terrain_height(*terrain, xy);
      for (const glm::vec2 d :
           {glm::vec2(1, 0), glm::vec2(-1, 0), glm::vec2(0, 1), glm::vec2(0, -1)})
        ground = std::max(ground, terrain_height(*terrain, xy + f.radius * d));
    }
    const float heading = a + (f.speed >= 0 ? 0.5f : -0.5f) * std::numbers::pi_v<float>;
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(xy, ground + f.hover));
    m = glm::rotate(m, heading, glm::vec3(0, 0, 1));
    m = glm::rotate(m, 0.5f * std::numbers::pi_v<float>, glm::vec3(1, 0, 0));  // glTF: y up
    m = glm::scale(m, glm::vec3(f.scale));
    out.world = glm::translate(m, -f.model_centre);
  });
}

void turn_sky(ecs::World& w) {
  ProbeSkyBake& bake = w.resource<ProbeSkyBake>();
  const EnvironmentLight* env = w.try_resource<const EnvironmentLight>();
  if (!bake.data || !env) return;
  const int shift = sky_shift(env->rotation_z, bake.data->w);
  if (shift == bake.shift) return;
  const auto t0 = std::chrono::steady_clock::now();
  w.resource<ProbeCloudResource>().replace(cloud_with_sh(bake, shift));
  bake.last_bake_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  bake.shift = shift;
  ++bake.bakes;
}

// E(n) / pi per vertex normal from the object's irradiance SH (engine/sh: E(n) = sum_i e_i
// y_i(n)), clamped at 0: radiance per unit albedo, as blockers.shade gives the boulders.
// The cloud was baked from the map at full intensity: EnvironmentLight::intensity scales it.
void shade(ecs::World& w) {
  const EnvironmentLight* env = w.try_resource<const EnvironmentLight>();
  const float intensity = env ? env->intensity : 1.0f;
  w.query<const ProbeLighting, const Transform, const ProbeShadedMesh, VertexLighting>().each(
      [&](const ProbeLighting& l, const Transform& t, const ProbeShadedMesh& m,
          VertexLighting& out) {
        if (!l.valid || !m.normals) return;  // no cloud yet: keeps what it had
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(t.world)));
        auto rgb = std::make_shared<std::vector<glm::vec3>>(m.normals->size());
        for (std::size_t i = 0; i < rgb->size(); ++i) {
          glm::vec3 n = nm * (*m.normals)[i];
          const float len = glm::length(n);
          n = len > 0 && std::isfinite(len) ? n / len : glm::vec3(0, 0, 1);
          const sh::Coeffs<ProbeLighting::kBands> y = sh::eval_basis<ProbeLighting::kBands>(n);
          glm::vec3 e(0.0f);
          for (int k = 0; k < sh::kCount<ProbeLighting::kBands>; ++k)
            e += y[k] * glm::vec3(l.irradiance[0][k], l.irradiance[1][k], l.irradiance[2][k]);
          (*rgb)[i] = glm::max(intensity * e, glm::vec3(0.0f)) * std::numbers::inv_pi_v<float>;
        }
        out.rgb = std::move(rgb);
      });
}

// A probe's irradiance averaged over normals (the SH's DC term) as a displayable HDR colour:
// Reinhard about the cloud's median: the median probe 1, dark ones towards 0, bright ones up to 2.
glm::vec3 probe_colour(const data::ProbeCloud& c, std::size_t p, float median) {
  const float* s = c.probe_sh(p);
  const std::size_t n = static_cast<std::size_t>(c.bands * c.bands);
  const glm::vec3 e = glm::max(glm::vec3(s[0], s[n], s[2 * n]), glm::vec3(0.0f));
  const float lum = 0.2126f * e.x + 0.7152f * e.y + 0.0722f * e.z;
  return 2.0f * e / (lum + median + 1e-20f);
}

void add_circle(std::vector<DebugLine>& out, const glm::vec3& c, float r, int axis,
                const glm::vec3& colour) {
  constexpr int kSegments = 8;
  glm::vec3 prev{};
  for (int k = 0; k <= kSegments; ++k) {
    const float a = 2 * std::numbers::pi_v<float> * k / kSegments;
    glm::vec3 q(0.0f);
    q[(axis + 1) % 3] = r * std::cos(a);
    q[(axis + 2) % 3] = r * std::sin(a);
    if (k > 0) out.push_back({prev, c + q, colour});
    prev = c + q;
  }
}

// A cell's centre for the walk path: an inner cell's centroid; an outer cell's hull triangle
// centroid moved out along its vertices' mean hull normal by a third of the triangle's size.
glm::vec3 cell_centre(const data::ProbeCloud& c, std::int32_t cell) {
  const data::ProbeCell& k = c.cells[static_cast<std::size_t>(cell)];
  if (!k.outer()) {
    glm::vec3 s(0.0f);
    for (std::int32_t v : k.vertices) s += c.positions[static_cast<std::size_t>(v)];
    return 0.25f * s;
  }
  glm::vec3 s(0.0f), n(0.0f);
  float size = 0;
  for (int i = 0; i < 3; ++i) {
    const auto v = static_cast<std::size_t>(k.vertices[i]);
    s += c.positions[v];
    n += c.hull_normals[v];
    size =
        std::max(size, glm::length(c.positions[v] -
                                   c.positions[static_cast<std::size_t>(k.vertices[(i + 1) % 3])]));
  }
  const float l = glm::length(n);
  return s / 3.0f + (l > 0 ? n / l : glm::vec3(0.0f)) * (size / 3.0f);
}

void probe_debug_view(ecs::World& w) {
  const ProbeDebugView& view = w.resource<const ProbeDebugView>();
  const probe_cloud::ProbeWalkState& state = w.resource<const probe_cloud::ProbeWalkState>();
  const probe_cloud::ProbeTetWalk* walk = state.walk.get();
  const bool on = view.enabled && walk;
  // The probes: three wire circles each, coloured by their irradiance.
  w.query<const ProbeCloudView, DebugLines>().each([&](const ProbeCloudView&, DebugLines& out) {
    out.lines.clear();
    if (!on) return;
    const data::ProbeCloud& c = walk->cloud();
    std::vector<float> lum(c.probe_count());
    const std::size_t n = static_cast<std::size_t>(c.bands * c.bands);
    for (std::size_t p = 0; p < lum.size(); ++p) {
      const float* s = c.probe_sh(p);
      lum[p] = 0.2126f * s[0] + 0.7152f * s[n] + 0.0722f * s[2 * n];
    }
    std::vector<float> sorted = lum;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const float median = sorted.empty() ? 1.0f : std::max(sorted[sorted.size() / 2], 1e-20f);
    out.lines.reserve(c.probe_count() * 24);
    for (std::size_t p = 0; p < c.probe_count(); ++p) {
      const glm::vec3 colour = probe_colour(c, p, median);
      for (int axis = 0; axis < 3; ++axis)
        add_circle(out.lines, c.positions[p], view.probe_radius, axis, colour);
    }
  });
  // Each object: the cell it uses (an inner cell's 6 edges, an outer cell's hull triangle and
  // its vertices' hull normals), and this frame's walk through the cells' centres.
  w.query<const ProbeAnchor, ProbeWalkTrace, DebugLines>().each(
      [&](const ProbeAnchor& a, ProbeWalkTrace& trace, DebugLines& out) {
        out.lines.clear();
        const std::int32_t start = trace.generation == state.generation ? trace.cell : -1;
        trace = {a.cell, a.generation};
        if (!on || a.cell < 0 || a.generation != state.generation) return;
        const data::ProbeCloud& c = walk->cloud();
        const data::ProbeCell& k = c.cells[static_cast<std::size_t>(a.cell)];
        const auto pos = [&](int i) {
          return c.positions[static_cast<std::size_t>(k.vertices[i])];
        };
        if (!k.outer()) {
          const glm::vec3 colour(4.0f, 3.2f, 0.4f);
          for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) out.lines.push_back({pos(i), pos(j), colour});
        } else {
          const glm::vec3 colour(4.0f, 1.2f, 0.2f);
          for (int i = 0; i < 3; ++i) {
            out.lines.push_back({pos(i), pos((i + 1) % 3), colour});
            const glm::vec3 nrm = c.hull_normals[static_cast<std::size_t>(k.vertices[i])];
            out.lines.push_back({pos(i), pos(i) + 1000.0f * nrm, colour});
          }
        }
        std::vector<std::int32_t> path;
        walk->locate(a.point, start, &path);
        glm::vec3 prev = a.point;
        for (std::size_t i = 0; i < path.size(); ++i) {
          const glm::vec3 q = cell_centre(c, path[i]);
          if (i > 0) out.lines.push_back({prev, q, {3.0f, 0.4f, 3.0f}});
          prev = q;
        }
        if (!path.empty()) out.lines.push_back({prev, a.point, {3.0f, 0.4f, 3.0f}});
      });
}

}  // namespace

void populate_probe_demo(ecs::World& world, const std::string& data_dir,
                         std::shared_ptr<const data::EnvironmentMap> map,
                         const ProbeDemoConfig& config) {
  world.emplace_resource<ProbeDebugView>(ProbeDebugView{config.show});
  world.emplace_resource<ProbeSkyBake>();
  if (config.count <= 0) {
    probe_cloud::emplace_probe_cloud_resources(world);  // no cloud: the systems do nothing
    return;
  }
  const Terrain* terrain = find_terrain(world);
  if (!terrain || !map) throw std::invalid_argument("probe demo: needs a terrain and a sky map");
  if (config.grid < 2 || config.heights.empty() || config.sky_steps < 1 || config.samples < 2)
    throw std::invalid_argument(
        "probe demo: grid >= 2, one height at least, sky_steps >= 1, "
        "samples >= 2");
  const auto t0 = std::chrono::steady_clock::now();

  // Probes: a grid over the terrain at each height above the local ground.
  const data::HeightField& f = *terrain->heights;
  const float extent = f.cell_size * static_cast<float>(f.width - 1);
  std::vector<glm::vec3> positions;
  for (float h : config.heights)
    for (int j = 0; j < config.grid; ++j)
      for (int i = 0; i < config.grid; ++i) {
        const glm::vec2 xy = glm::vec2(terrain->origin) +
                             extent * glm::vec2(i, j) / static_cast<float>(config.grid - 1);
        positions.emplace_back(xy, terrain_height(*terrain, xy) + h);
      }
  const glm::vec2 centre = glm::vec2(terrain->origin) + 0.5f * extent;
  const std::vector<glm::vec3> extra =
      config.extra_probes ? config.extra_probes(*terrain) : std::vector<glm::vec3>{};
  for (const glm::vec3& p : extra) {
    const glm::vec2 xy = centre + extent * glm::vec2(p);
    positions.emplace_back(xy, terrain_height(*terrain, xy) + p.z);
  }
  probe_cloud::ProbeCloudBuildSettings build;
  build.bands = kCloudBands;
  auto data = std::make_shared<ProbeSkyBake::Data>();
  data->cloud = probe_cloud::build_probe_cloud(positions, {}, build);

  // Their lighting: the bake's capture per sky step (probe_sky_bake.h), from the cache when it
  // has them; the field at the demo's vertical exaggeration, as the terrain system sees it.
  data->w = config.sky_steps;
  data->field = f;
  for (float& v : data->field.heights) v *= terrain->height_scale;
  data->map = std::move(map);
  data->inputs.field = &data->field;
  data->inputs.origin = terrain->origin;
  data->inputs.albedo = terrain->albedo;
  data->inputs.map = data->map.get();
  data->inputs.steps = config.sky_steps;
  data->inputs.samples = config.samples;
  data->inputs.bounce = config.bounce;
  if (config.bake_meshes) data->inputs.meshes = config.bake_meshes(*terrain);
  data->cache_dir = config.cache_dir;
  const std::vector<int> first = {0};
  ProbeSkySteps steps =
      bake_probe_sky_steps(data->inputs, data->cloud, data->cache_dir,
                           config.sky_turns ? std::span<const int>() : std::span<const int>(first));
  data->steps = std::move(steps.sh);
  ProbeSkyBake& bake = world.resource<ProbeSkyBake>();
  bake.steps_baked = steps.baked;
  bake.steps_loaded = steps.loaded;
  bake.bake_seconds = steps.seconds;
  bake.cache_folder = steps.folder.string();
  bake.notes = std::move(steps.notes);
  bake.data = std::move(data);
  probe_cloud::emplace_probe_cloud_resources(world, cloud_with_sh(bake, 0));
  bake.bakes = 1;

  // The objects: the models simplified as the boulders', bunny and Suzanne alternating.
  struct Model {
    std::shared_ptr<const data::MeshData> mesh;
    std::shared_ptr<const std::vector<glm::vec3>> normals;
    glm::vec3 centre{0.0f};
    float radius = 1;
  };
  std::vector<Model> models;
  for (const char* name : {"suzi", "bunny"}) {
    const std::filesystem::path file =
        std::filesystem::path(data_dir) / "models" / (std::string(name) + ".glb");
    auto mesh = std::make_shared<data::MeshData>(assets::merge_instances(assets::load_gltf(file)));
    if (config.simplify_error > 0)
      *mesh = assets::simplify_mesh(*mesh, {0.1f, config.simplify_error}).mesh;
    Model m;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : mesh->positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    m.centre = 0.5f * (lo + hi);
    m.radius = 0;
    for (const glm::vec3& p : mesh->positions)
      m.radius = std::max(m.radius, glm::length(p - m.centre));
    m.normals = std::make_shared<const std::vector<glm::vec3>>(data::vertex_normals(*mesh));
    m.mesh = std::move(mesh);
    models.push_back(std::move(m));
  }
  for (int i = 0; i < config.count; ++i) {
    const Model& m = models[static_cast<std::size_t>(i % 2)];
    ProbeFloater fl;
    fl.path_radius = extent * (0.1f + 0.3f * static_cast<float>(i) / config.count);
    fl.phase = 1.3f + 2.4f * static_cast<float>(i);
    fl.speed = (i % 2 ? -1.0f : 1.0f) * (220.0f + 30.0f * static_cast<float>(i % 3));
    fl.hover = config.hover;
    fl.radius = config.radius;
    fl.scale = config.radius / std::max(m.radius, 1e-6f);
    fl.model_centre = m.centre;
    world.create_with(fl, Transform{}, components::MeshInstance{m.mesh},
                      components::Material{glm::vec3(0.7f), 0.0f}, ProbeAnchor{}, ProbeLighting{},
                      ProbeShadedMesh{m.normals}, VertexLighting{}, ProbeWalkTrace{}, DebugLines{});
  }
  world.create_with(ProbeCloudView{}, DebugLines{});
  world.resource<ProbeSkyBake>().startup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void add_probe_demo_systems(jobs::Schedule& s) {
  s.add_task("demo_probe_floaters", [](jobs::SystemContext& ctx) { float_along(ctx.world()); })
      .reads<FrameTime, Terrain, ProbeFloater>()
      .writes<Transform>();
  s.add_task("demo_probe_sky", [](jobs::SystemContext& ctx) { turn_sky(ctx.world()); })
      .reads<EnvironmentLight>()
      .writes<ProbeSkyBake, ProbeCloudResource>();
  probe_cloud::add_probe_cloud_systems(s);
  s.add_task("demo_probe_shade", [](jobs::SystemContext& ctx) { shade(ctx.world()); })
      .reads<ProbeLighting, Transform, ProbeShadedMesh, EnvironmentLight>()
      .writes<VertexLighting>();
  s.add_task("demo_probe_debug", [](jobs::SystemContext& ctx) { probe_debug_view(ctx.world()); })
      .reads<ProbeDebugView, probe_cloud::ProbeWalkState, ProbeAnchor, ProbeCloudView>()
      .writes<DebugLines, ProbeWalkTrace>();
}

}  // namespace penumbra::game
