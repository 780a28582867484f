// Benchmark group "spherical_lights" (issue 13, [Guerrero08] sec. 5-7): one-bounce indirect light
// from sphere sets, 4 bands. Scenes (built once, outside the timed loops):
//  - objects:64  8 boxes (1.5-3 m a side, turned about z, 0.3 m above the ground, one colour
//                each), 8 SLs each (the octants' circumscribed spheres: 64 SLs), scattered over
//                30 m x 30 m; 100,000 receivers: a 300 x 300 grid on the ground (z = 0, up)
//                over 50 m x 50 m around and under them, and 10,000 points on the boxes' faces
//                (area-weighted, the face normals);
//  - squirrel:14 one box 2 x 1 x 3.5 m cut into 2 x 1 x 7 cells (14 SLs, [Guerrero08] sec. 8's
//                squirrel: 21k vertices, 14 leaf SLs); 21,000 receivers: 10,506 on the ground
//                (10 m x 10 m) and 10,494 on its faces.
// Direct light: a sky of radiance 0.4 + 1.6 max(0, z)^2 (slightly blue), as a 64 x 32 map for the
// reference and its 4-band projection for ours. Sample points: sample_reflector (92 directions
// per SL); pass 1: ReflectorLighting::update per object with every SL of the scene as a blocker.
// Cases:
//  - BM_PerLight/<blocking>/<min_sin>: single thread (CPU clock), SphereLightGather::irradiance at
//    every 25th receiver of objects:64 (4,000); per receiver per SL = time / (4,000 x 64);
//  - BM_Update/<threads>: pass 1 for all 8 objects (set_blockers + update + place), 1 or 2
//    threads (parallel over objects);
//  - BM_Frame/<scene>/<blocking>[/<min_sin>]: set_lights + shade of every receiver on 2 threads
//    (tbb arena of 2, parallel_for over blocks of 1,024), wall clock.
// Counters (outside the timed loop, every receiver, single thread): the gather's own Counts
// (lights looked at, views, emitters, overlap tests, log caps, exponentials) -> the counted
// operations of a frame (the floor); accuracy at every 100th receiver (objects:64) or 21st
// (squirrel:14): indirect irradiance against reference::indirect_irradiance (one diffuse bounce
// off the boxes' meshes with their albedo, the same sky; 512 directions, 8 per hit), relative RMS
// sqrt(sum |E - E_ref|^2 / sum |E_ref|^2) and max |E - E_ref| / RMS(E_ref), RGB together, and
// the reference's own relative standard error.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "../spherical_lights/test_meshes.h"
#include "bench_registry.h"
#include "common/random_draws.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/spherical_lights/reflector_lighting.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "spherical_light_bench.h"

namespace {
namespace pb = penumbra::bench;
namespace ps = penumbra::bench::spherical;
namespace ba = penumbra::blocker_accumulation;
namespace sl = penumbra::spherical_lights;
namespace sh = penumbra::sh;
namespace data = penumbra::data;
namespace ref = penumbra::reference;

constexpr int N = 4;
constexpr int kThreads = 2;
constexpr std::size_t kBlock = 1024;
constexpr std::size_t kPerLightStride = 25;
constexpr double kGoalObjectsMs = 30;  // issue 13: 100,000 receivers x 64 SLs, 2 cores
constexpr double kGoalSquirrelMs = 3;  // issue 13: 21,000 receivers x 14 SLs, 2 cores
constexpr float kDefaultMinSin = sl::SphereLightSettings{}.blocker.min_sin;

// --- Scenes -------------------------------------------------------------------------------------

// The circumscribed spheres of a g.x x g.y x g.z grid of cells over the box (the fitted set's
// stand-in: every sphere bounds its cell, neighbours intersect).
std::vector<data::Sphere> cell_spheres(glm::vec3 h, glm::ivec3 g) {
  std::vector<data::Sphere> out;
  const glm::vec3 cell = 2.0f * h / glm::vec3(g);
  for (int z = 0; z < g.z; ++z)
    for (int y = 0; y < g.y; ++y)
      for (int x = 0; x < g.x; ++x)
        out.push_back({-h + cell * (glm::vec3(x, y, z) + 0.5f), 0.5f * glm::length(cell), -1});
  return out;
}

struct Object {
  glm::vec3 half{1.0f};
  data::MeshData mesh;
  std::vector<data::Sphere> spheres;
  sl::ObjectPose pose;
  glm::vec3 albedo{0.5f};
  sl::ReflectorSamples samples;
};

struct Scene {
  std::vector<Object> objects;
  std::vector<glm::vec3> points, normals;
  std::size_t lights = 0;
  std::size_t accuracy_stride = 100;
};

glm::vec3 sky_radiance(const glm::vec3& d) {
  const float z = std::max(d.z, 0.0f);
  return (0.4f + 1.6f * z * z) * glm::vec3(0.85f, 0.95f, 1.1f);
}

data::EnvironmentMap sky_map() {
  data::EnvironmentMap m;
  m.width = 64;
  m.height = 32;
  m.source = "bench sky";
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const glm::vec3 c =
          sky_radiance(sh::equirect_direction((x + 0.5f) / m.width, (y + 0.5f) / m.height));
      m.rgb.insert(m.rgb.end(), {c.x, c.y, c.z});
    }
  return m;
}

const sh::CoeffsRgb<N>& sky_sh() {
  static const sh::CoeffsRgb<N> s = [] {
    const data::EnvironmentMap m = sky_map();
    return sh::project_equirect<N>(m.rgb.data(), m.width, m.height);
  }();
  return s;
}

void add_object(Scene& s, glm::vec3 half, glm::ivec3 cells, glm::vec2 xy, float turn,
                glm::vec3 albedo) {
  Object o;
  o.half = half;
  o.albedo = albedo;
  o.mesh = sl::test::box_mesh(-half, half, albedo);
  o.spheres = cell_spheres(half, cells);
  o.pose.rotation = glm::mat3(glm::rotate(glm::mat4(1.0f), turn, glm::vec3(0, 0, 1)));
  o.pose.translation = glm::vec3(xy, 0.3f + half.z);
  o.samples = sl::sample_reflector(o.mesh, o.spheres);
  s.lights += o.spheres.size();
  s.objects.push_back(std::move(o));
}

void add_ground(Scene& s, int nx, int ny, float half_extent) {
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      s.points.push_back(glm::vec3(-half_extent + 2 * half_extent * (i + 0.5f) / nx,
                                   -half_extent + 2 * half_extent * (j + 0.5f) / ny, 0.0f));
      s.normals.push_back(glm::vec3(0, 0, 1));
    }
}

// `count` points on the objects' faces, area-weighted, with the face normals (world).
void add_surface(Scene& s, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1), pick(0, 1);
  double total = 0;
  for (const Object& o : s.objects)
    total += 8.0 * (o.half.x * o.half.y + o.half.y * o.half.z + o.half.z * o.half.x);
  for (std::size_t k = 0; k < count; ++k) {
    double t = pick(rng) * total;
    const Object* o = &s.objects.back();
    for (const Object& c : s.objects) {
      const double a = 8.0 * (c.half.x * c.half.y + c.half.y * c.half.z + c.half.z * c.half.x);
      if (t < a) {
        o = &c;
        break;
      }
      t -= a;
    }
    const glm::vec3 h = o->half;
    const float areas[3] = {h.y * h.z, h.x * h.z, h.x * h.y};  // faces normal to x, y, z
    float f = pick(rng) * (areas[0] + areas[1] + areas[2]);
    int axis = 0;
    while (axis < 2 && f >= areas[axis]) f -= areas[axis], ++axis;
    const float side = pick(rng) < 0.5f ? -1.0f : 1.0f;
    glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u) * h, n(0.0f);
    p[axis] = side * h[axis];
    n[axis] = side;
    s.points.push_back(o->pose.rotation * p + o->pose.translation);
    s.normals.push_back(o->pose.rotation * n);
  }
}

Scene objects_scene() {
  Scene s;
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> xy(-15, 15), size(0.75f, 1.5f), turn(0, 6.2831853f);
  const glm::vec3 colours[8] = {{0.8f, 0.15f, 0.1f}, {0.1f, 0.7f, 0.2f}, {0.15f, 0.3f, 0.85f},
                                {0.9f, 0.8f, 0.1f},  {0.8f, 0.8f, 0.8f}, {0.7f, 0.2f, 0.7f},
                                {0.1f, 0.7f, 0.7f},  {0.9f, 0.5f, 0.1f}};
  std::vector<glm::vec2> placed;
  while (placed.size() < 8) {
    const float cy = xy(rng), cx = xy(rng);  // GCC's order (random_draws.h)
    const glm::vec2 c(cx, cy);
    bool free = true;
    for (const glm::vec2& q : placed) free = free && glm::length(c - q) > 6.0f;
    if (!free) continue;
    placed.push_back(c);
    const float angle = turn(rng);  // before the size: GCC's order (random_draws.h)
    add_object(s, penumbra::test::draw_zyx<glm::vec3>(rng, size), glm::ivec3(2), c, angle,
               colours[placed.size() - 1]);
  }
  add_ground(s, 300, 300, 25.0f);
  add_surface(s, 10'000, 7);
  s.accuracy_stride = 100;
  return s;
}

Scene squirrel_scene() {
  Scene s;
  add_object(s, glm::vec3(1.0f, 0.5f, 1.75f), glm::ivec3(2, 1, 7), glm::vec2(0.0f), 0.4f,
             glm::vec3(0.8f, 0.4f, 0.15f));
  add_ground(s, 103, 102, 5.0f);
  add_surface(s, 21'000 - s.points.size(), 11);
  s.accuracy_stride = 21;
  return s;
}

const Scene& scene(const std::string& name) {
  static const std::map<std::string, Scene> scenes = [] {
    std::map<std::string, Scene> m;
    m["objects:64"] = objects_scene();
    m["squirrel:14"] = squirrel_scene();
    return m;
  }();
  return scenes.at(name);
}

// Pass 1 ([Guerrero08] sec. 5): blockers of the whole scene, L^c per SL, SLs in the world.
struct Lit {
  std::unique_ptr<sl::ReflectorLighting<N>> lighting;
  std::unique_ptr<ba::BlockerAccumulation<N>> blockers;
  std::vector<ba::WorldSphere> spheres;
  std::vector<ba::BlockerGroup> groups;
  std::vector<std::vector<sh::CoeffsRgb<N>>> radiance;  // per object, per SL
  std::vector<sl::SphereLightSource<N>> lights;
};

void world_spheres(const Scene& s, std::vector<ba::WorldSphere>& spheres,
                   std::vector<ba::BlockerGroup>& groups) {
  spheres.clear();
  groups.clear();
  for (const Object& o : s.objects) {
    const auto first = static_cast<std::uint32_t>(spheres.size());
    for (const data::Sphere& sp : o.spheres)
      spheres.push_back({o.pose.rotation * (o.pose.scale * sp.centre) + o.pose.translation,
                         o.pose.scale * sp.radius});
    groups.push_back(ba::bound_group(std::span(spheres).subspan(first), first));
  }
}

const Lit& lit(const std::string& name) {
  static std::map<std::string, Lit> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  const Scene& s = scene(name);
  Lit l;
  l.lighting = std::make_unique<sl::ReflectorLighting<N>>(s.objects[0].samples.directions);
  l.blockers = std::make_unique<ba::BlockerAccumulation<N>>();
  world_spheres(s, l.spheres, l.groups);
  l.blockers->set_blockers(l.spheres, l.groups);
  for (std::uint32_t o = 0; o < s.objects.size(); ++o) {
    l.radiance.push_back(
        l.lighting->update(s.objects[o].samples, s.objects[o].pose, *l.blockers, sky_sh()));
    sl::ReflectorLighting<N>::place(s.objects[o].samples, s.objects[o].pose, l.radiance.back(), o,
                                    l.lights);
  }
  return cache.emplace(name, std::move(l)).first->second;
}

sl::SphereLightSettings settings_for(const std::string& blocking, float min_sin) {
  sl::SphereLightSettings s;
  s.blocking = blocking == "per_object" ? sl::SlBlocking::kPerObject : sl::SlBlocking::kPerSphere;
  s.blocker.min_sin = min_sin;
  return s;
}

// --- Counted operations (the floors) ----------------------------------------------------------

// eval_basis<4> (blocker_bench.cpp's count) and the SH product's factored terms.
constexpr double kBasis = 35;
constexpr double kC = N * N;
double product_terms() {
  return sh::factored_term_count<N>();
}
// Per SL looked at: view_blocker (41, the blockers group's count) + the centre distance (4).
constexpr double kViewOps = 45;
// Per emitter: eq. 18 (to_local 9, normalise 6, basis, 3 x (N ZH scales + C FMAs)) and the cap
// integral (about 20).
constexpr double kEmitterOps = 9 + 6 + kBasis + 3 * (N + kC) + 20;
// Per far SL at a receiver (shade(clusters)): difference 3, dot 3, d^2 3, s^2 1, sqrt x2, the
// min_sin fade 6, the product and 3 FMAs.
constexpr double kFarOps = 22;
// Per overlap test: one dot and two compares (no acos: the floor compares cosines).
constexpr double kPairOps = 4;
// add_log_visibility<4>: as blocker_bench.cpp's add_log_flops(4).
constexpr double kLogOps = 3 + 3 * (N - 1) + kBasis + 1 + 3 * N + kC;
// exp_visibility<4> with one HYB squaring (6 C + 23 + terms).
double exp_ops() {
  return 6 * kC + 23 + product_terms();
}
// A blocked emitter besides its logs: 3 exponentials, the sums, the clamped cosine's rotation
// (basis + N + C, shared per receiver: counted once per blocked emitter, an upper bound) and
// the dot.
double blocked_ops() {
  return 3 * exp_ops() + 3 * kC + kBasis + N + kC + kC;
}
double gather_ops(const sl::SphereLightGather<N>::Counts& c) {
  return static_cast<double>(c.lights) * kViewOps + static_cast<double>(c.emitters) * kEmitterOps +
         static_cast<double>(c.pairs) * kPairOps + static_cast<double>(c.logs) * kLogOps +
         static_cast<double>(c.blocked) * blocked_ops() + static_cast<double>(c.far) * kFarOps;
}

// Pass 1 per object: per sample point the blockers' log sum (views, adds) and shade (exp,
// clamped-cosine rotation, product, 3 dots); per SL the Voronoi projection (92 x 3 C) twice
// (radiance and albedo) and the albedo product (3 x terms).
double update_ops(const std::string& name) {
  const Scene& s = scene(name);
  const Lit& l = lit(name);
  typename ba::BlockerAccumulation<N>::PairCounts counts;
  double points = 0, lights = 0;
  for (const Object& o : s.objects) {
    for (const sl::SphereSamples& ss : o.samples.lights) {
      lights += 1;
      for (std::size_t j = 0; j < ss.valid.size(); ++j) {
        if (!ss.valid[j]) continue;
        points += 1;
        const glm::vec3 p = o.pose.rotation * ss.positions[j] + o.pose.translation;
        l.blockers->log_visibility(p, o.pose.rotation * ss.normals[j], &counts);
      }
    }
  }
  const double dirs = static_cast<double>(s.objects[0].samples.directions.size());
  const double shade = exp_ops() + kBasis + N + kC + product_terms() + 3 * kC;
  return static_cast<double>(counts.views) * 41 + static_cast<double>(counts.adds) * kLogOps +
         points * shade + lights * (2 * dirs * 3 * kC + 3 * product_terms());
}

// --- Analysis (outside the timed loops) -------------------------------------------------------

struct Analysis {
  sl::SphereLightGather<N>::Counts counts;  // every receiver
  double receivers = 0, ops = 0;
  std::optional<double> rel_rms, max_rel, ref_rel_se, bias;
  std::optional<double> rel_rms_vs_exact;  // clusters: against per receiver, every receiver
  double accuracy_receivers = 0;
};

struct Reference {
  std::vector<std::size_t> index;
  std::vector<ref::RgbEstimate> estimate;
};

const Reference& reference(const std::string& name) {
  static std::map<std::string, Reference> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  const Scene& s = scene(name);
  ref::SceneDesc desc;
  desc.environment = ref::EnvironmentLight{sky_map(), 0.0f};
  for (const Object& o : s.objects) {
    glm::mat4 t(o.pose.rotation);
    t[3] = glm::vec4(o.pose.translation, 1.0f);
    desc.meshes.push_back({o.mesh, t, o.albedo});
  }
  const ref::Scene rs(desc);
  Reference r;
  std::vector<ref::Receiver> receivers;
  for (std::size_t i = 0; i < s.points.size(); i += s.accuracy_stride) {
    r.index.push_back(i);
    receivers.push_back({s.points[i], s.normals[i]});
  }
  ref::BounceOptions options;
  options.samples = 512;
  options.bounce_samples = 8;
  options.seed = 13;
  r.estimate = ref::indirect_irradiance(rs, receivers, options);
  return cache.emplace(name, std::move(r)).first->second;
}

const sl::SlReceiverClusters& clusters(const std::string& name, float far_ratio) {
  static std::map<std::pair<std::string, float>, sl::SlReceiverClusters> cache;
  auto it = cache.find({name, far_ratio});
  if (it != cache.end()) return it->second;
  sl::SlClusterSettings cs;
  cs.far_ratio = far_ratio;
  const Scene& s = scene(name);
  return cache.emplace(std::pair(name, far_ratio), sl::cluster_receivers(s.points, s.normals, cs))
      .first->second;
}

const Analysis& analyse(const ps::FrameCaseInfo& c) {
  static std::map<std::string, Analysis> cache;
  const std::string& name = c.scene;
  const std::string key = c.key;
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const Scene& s = scene(name);
  sl::SphereLightGather<N> gather(settings_for(c.blocking, c.min_sin));
  gather.set_lights(lit(name).lights);
  Analysis a;
  a.receivers = static_cast<double>(s.points.size());
  std::vector<glm::vec3> all(s.points.size());
  if (c.method == "clusters") {
    gather.shade(clusters(name, c.far_ratio), all, &a.counts);
    double d2 = 0, e2 = 0;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const glm::vec3 e = gather.irradiance(s.points[i], s.normals[i]), d = all[i] - e;
      d2 += glm::dot(d, d), e2 += glm::dot(e, e);
    }
    if (e2 > 0) a.rel_rms_vs_exact = std::sqrt(d2 / e2);
  } else {
    for (std::size_t i = 0; i < s.points.size(); ++i)
      all[i] = gather.irradiance(s.points[i], s.normals[i], &a.counts);
  }
  a.ops = gather_ops(a.counts);
  const Reference& r = reference(name);
  double diff2 = 0, ref2 = 0, se2 = 0, max_diff = 0, sum = 0, ref_sum = 0;
  for (std::size_t k = 0; k < r.index.size(); ++k) {
    const std::size_t i = r.index[k];
    const glm::vec3 d = all[i] - r.estimate[k].mean;
    diff2 += glm::dot(d, d);
    ref2 += glm::dot(r.estimate[k].mean, r.estimate[k].mean);
    se2 += glm::dot(r.estimate[k].std_error, r.estimate[k].std_error);
    sum += all[i].x + all[i].y + all[i].z;
    ref_sum += r.estimate[k].mean.x + r.estimate[k].mean.y + r.estimate[k].mean.z;
    max_diff = std::max(max_diff, static_cast<double>(glm::length(d)));
  }
  a.accuracy_receivers = static_cast<double>(r.index.size());
  if (ref2 > 0) {
    a.rel_rms = std::sqrt(diff2 / ref2);
    a.max_rel = max_diff / std::sqrt(ref2 / static_cast<double>(r.index.size()));
    a.ref_rel_se = std::sqrt(se2 / ref2);
    a.bias = sum / ref_sum;
  }
  return cache.emplace(key, a).first->second;
}

// --- Benchmarks ---------------------------------------------------------------------------------

void BM_PerLight(benchmark::State& state, std::string blocking, float min_sin) {
  const Scene& s = scene("objects:64");
  sl::SphereLightGather<N> gather(settings_for(blocking, min_sin));
  gather.set_lights(lit("objects:64").lights);
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < s.points.size(); i += kPerLightStride) idx.push_back(i);
  for (auto _ : state) {
    glm::vec3 sum(0.0f);
    for (std::size_t i : idx) sum += gather.irradiance(s.points[i], s.normals[i]);
    benchmark::DoNotOptimize(sum);
  }
  sl::SphereLightGather<N>::Counts c;
  for (std::size_t i : idx) gather.irradiance(s.points[i], s.normals[i], &c);
  state.counters["receivers"] = static_cast<double>(idx.size());
  state.counters["lights"] = static_cast<double>(s.lights);
  state.counters["ops"] = gather_ops(c);
  state.counters["views_per_receiver"] =
      static_cast<double>(c.views) / static_cast<double>(idx.size());
}

void BM_Update(benchmark::State& state) {
  const std::string name = "objects:64";
  const Scene& s = scene(name);
  const Lit& l = lit(name);
  const int threads = static_cast<int>(state.range(0));
  tbb::task_arena arena(threads);
  ba::BlockerAccumulation<N> blockers;
  std::vector<ba::WorldSphere> spheres;
  std::vector<ba::BlockerGroup> groups;
  std::vector<std::vector<sh::CoeffsRgb<N>>> radiance(s.objects.size());
  std::vector<std::vector<sl::SphereLightSource<N>>> placed(s.objects.size());
  for (auto _ : state) {
    world_spheres(s, spheres, groups);
    blockers.set_blockers(spheres, groups);
    arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, s.objects.size(), [&](std::size_t o) {
        radiance[o] =
            l.lighting->update(s.objects[o].samples, s.objects[o].pose, blockers, sky_sh());
        placed[o].clear();
        sl::ReflectorLighting<N>::place(s.objects[o].samples, s.objects[o].pose, radiance[o],
                                        static_cast<std::uint32_t>(o), placed[o]);
      });
    });
    benchmark::DoNotOptimize(radiance.data());
    benchmark::ClobberMemory();
  }
  static const double ops = update_ops(name);
  double points = 0;
  for (const Object& o : s.objects)
    for (const sl::SphereSamples& ss : o.samples.lights) points += ss.count();
  state.counters["ops"] = ops;
  state.counters["sample_points"] = points;
  state.counters["lights"] = static_cast<double>(s.lights);
}

void BM_Frame(benchmark::State& state, ps::FrameCaseInfo c) {
  const std::string& name = c.scene;
  const Scene& s = scene(name);
  const Lit& l = lit(name);
  sl::SphereLightGather<N> gather(settings_for(c.blocking, c.min_sin));
  const sl::SlReceiverClusters* rc =
      c.method == "clusters" ? &clusters(name, c.far_ratio) : nullptr;
  tbb::task_arena arena(kThreads);
  std::vector<glm::vec3> out(s.points.size());
  const std::span<const glm::vec3> points(s.points), normals(s.normals);
  const std::span<glm::vec3> irradiance(out);
  for (auto _ : state) {
    gather.set_lights(l.lights);
    if (rc) {
      arena.execute([&] { gather.shade(*rc, irradiance); });
      benchmark::DoNotOptimize(out.data());
      benchmark::ClobberMemory();
      continue;
    }
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kBlock),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          gather.shade(points.subspan(r.begin(), r.size()),
                                       normals.subspan(r.begin(), r.size()),
                                       irradiance.subspan(r.begin(), r.size()));
                        });
    });
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  const Analysis& a = analyse(c);
  const double r = a.receivers;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(r));
  state.counters["receivers"] = r;
  state.counters["lights"] = static_cast<double>(s.lights);
  state.counters["ops_per_frame"] = a.ops;
  state.counters["views_per_receiver"] = static_cast<double>(a.counts.views) / r;
  state.counters["emitters_per_receiver"] = static_cast<double>(a.counts.emitters) / r;
  state.counters["pairs_per_receiver"] = static_cast<double>(a.counts.pairs) / r;
  state.counters["logs_per_receiver"] = static_cast<double>(a.counts.logs) / r;
  state.counters["exponentials_per_receiver"] = static_cast<double>(a.counts.exponentials) / r;
  state.counters["far_per_receiver"] = static_cast<double>(a.counts.far) / r;
  state.counters["accuracy_receivers"] = a.accuracy_receivers;
  if (a.rel_rms_vs_exact) state.counters["rel_rms_vs_per_receiver"] = *a.rel_rms_vs_exact;
  if (a.rel_rms) {
    state.counters["rel_rms_vs_reference"] = *a.rel_rms;
    state.counters["max_rel_vs_reference"] = *a.max_rel;
    state.counters["reference_rel_std_error"] = *a.ref_rel_se;
    state.counters["sum_vs_reference"] = *a.bias;
  }
}

std::string min_sin_text(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string frame_key(const std::string& scene, const std::string& blocking,
                      const std::string& method) {
  return "BM_Frame/" + scene + "/" + blocking + "/" + method;
}
std::string sweep_key(const std::string& blocking, const std::string& method, float min_sin,
                      float far_ratio) {
  std::string k = "BM_Frame/objects:64/" + blocking + "/" + method + "/min_sin:";
  k += min_sin_text(min_sin);
  if (method == "clusters") k += "/far:" + min_sin_text(far_ratio);
  return k;
}
std::string per_light_key(const std::string& blocking, float min_sin) {
  return "BM_PerLight/" + blocking + "/min_sin:" + min_sin_text(min_sin);
}

const char* const kBlockings[] = {"per_sphere", "per_object"};
constexpr float kFarRatio = sl::SlClusterSettings{}.far_ratio;
// The sweep (objects:64, besides the frames' default min_sin and far_ratio): per receiver at
// min_sin 0 (every SL: the baseline) and 0.02, 0.1; clusters at far_ratio 0.1, 0.25 and min_sin
// 0.02, 0.1.
struct SweepCase {
  const char* method;
  float min_sin, far_ratio;
};
constexpr SweepCase kSweep[] = {{"receivers", 0.0f, 0},       {"receivers", 0.02f, 0},
                                {"receivers", 0.1f, 0},       {"clusters", 0.05f, 0.1f},
                                {"clusters", 0.05f, 0.25f},   {"clusters", 0.02f, kFarRatio},
                                {"clusters", 0.1f, kFarRatio}};

using pb::fmt;

void register_benchmarks() {
  const pb::Timing cpu{.clock = pb::Timing::Clock::kCpu, .unit = benchmark::kMicrosecond};
  const pb::Timing ms_cpu{.clock = pb::Timing::Clock::kCpu,
                          .unit = benchmark::kMillisecond,
                          .iterations = 3,
                          .repetitions = 3};
  const pb::Timing frame{.unit = benchmark::kMillisecond, .iterations = 3, .repetitions = 5};
  const pb::Timing sweep{.unit = benchmark::kMillisecond, .iterations = 2, .repetitions = 3};
  pb::add("BM_FmaThroughput", cpu, pb::BM_FmaThroughput);
  for (const char* b : kBlockings) {
    pb::add(per_light_key(b, kDefaultMinSin), ms_cpu, BM_PerLight, std::string(b), kDefaultMinSin);
    pb::add(per_light_key(b, 0.0f), ms_cpu, BM_PerLight, std::string(b), 0.0f);
  }
  pb::add("BM_Update", {.unit = benchmark::kMillisecond, .iterations = 5, .repetitions = 3},
          BM_Update)
      ->Arg(1)
      ->Arg(kThreads);
  for (const ps::FrameCaseInfo& c : ps::frame_cases()) {
    pb::add(c.key, c.kind == "frame" ? frame : sweep, BM_Frame, c);
  }
}

pb::Row& add_row(pb::Summary& s, std::string name, std::string unit, std::optional<double> value,
                 std::optional<double> baseline, pb::Goal goal, std::optional<double> floor,
                 std::string note) {
  pb::Row& row = s.add_vs_baseline(std::move(name), std::move(unit), value, baseline, goal, floor,
                                   std::move(note));
  if (!baseline) row.ratio_def.clear();
  return row;
}

pb::Summary summarize(const pb::Results& r, const ps::Outputs& out) {
  pb::Summary s;
  const double ns_per_fma =
      pb::add_fma_floor_row(r, s, "8 independent chains; floors = counted operations x this");
  const auto ms = [&](const std::string& k) { return pb::scale(r.real_ns(k), 1e-6); };
  for (const char* b : kBlockings) {
    for (float m : {kDefaultMinSin, 0.0f}) {
      const std::string k = per_light_key(b, m);
      const auto m_ = r.get(k);
      const double pairs =
          r.counter(k, "receivers").value_or(0) * r.counter(k, "lights").value_or(0);
      const auto value = m_ && pairs > 0 ? std::optional<double>(m_->cpu_ns / pairs) : std::nullopt;
      const auto ops = r.counter(k, "ops");
      const std::optional<double> floor =
          ops && pairs > 0 ? std::optional<double>(*ops / pairs * ns_per_fma) : std::nullopt;
      const auto base = m > 0 ? r.get(per_light_key(b, 0.0f)) : std::nullopt;
      add_row(s, std::string("per receiver per SL, ") + b + ", min_sin " + min_sin_text(m), "ns",
              value, base && pairs > 0 ? std::optional<double>(base->cpu_ns / pairs) : std::nullopt,
              pb::Goal::none(), floor,
              "1 thread, 4,000 receivers of objects:64 x 64 SLs; " +
                  fmt("%.1f", r.counter(k, "views_per_receiver").value_or(NAN)) +
                  " SLs past the plane rule per receiver" + (m > 0 ? "; baseline: min_sin 0" : ""));
    }
  }
  for (int t : {1, kThreads}) {
    const std::string k = "BM_Update/" + std::to_string(t);
    const auto ops = r.counter(k, "ops");
    add_row(s, "pass 1: sample-point update, 8 objects, " + std::to_string(t) + " thread(s)", "ms",
            ms(k), t == 1 ? std::nullopt : ms("BM_Update/1"), pb::Goal::none(),
            ops ? std::optional<double>(*ops * ns_per_fma / t * 1e-6) : std::nullopt,
            fmt("%.0f", r.counter(k, "sample_points").value_or(NAN)) +
                " sample points, 64 SLs: blockers' log sum + shade per point, Voronoi sums and "
                "albedo product per SL (eq. 3-11)" +
                (t == 1 ? "" : "; baseline: 1 thread"));
  }
  for (const ps::FrameCaseInfo& c : ps::frame_cases()) {
    const auto floor = ps::frame_floor_ms(r, c.key, ns_per_fma);
    const auto rel = r.counter(c.key, "rel_rms_vs_reference");
    std::string note =
        fmt("%.0f receivers, ", c.receivers) + fmt("%.0f SLs, ", c.lights) +
        fmt("%.1f views, ", r.counter(c.key, "views_per_receiver").value_or(NAN)) +
        fmt("%.2f log caps, ", r.counter(c.key, "logs_per_receiver").value_or(NAN)) +
        fmt("%.2f exps per receiver", r.counter(c.key, "exponentials_per_receiver").value_or(NAN));
    if (rel)
      note += "; indirect vs reference: rel RMS " + fmt("%.3g%%", 100 * *rel) + ", max " +
              fmt("%.3g%%", 100 * r.counter(c.key, "max_rel_vs_reference").value_or(NAN)) +
              " (reference noise " +
              fmt("%.2g%%", 100 * r.counter(c.key, "reference_rel_std_error").value_or(NAN)) +
              "; sum / reference sum " +
              fmt("%.3f", r.counter(c.key, "sum_vs_reference").value_or(NAN)) + ")";
    if (auto v = r.counter(c.key, "rel_rms_vs_per_receiver"))
      note += "; vs per receiver: rel RMS " + fmt("%.3g%%", 100 * *v);
    std::optional<double> baseline;
    if (c.kind == "frame" && c.method == "clusters") {
      baseline = ms(frame_key(c.scene, c.blocking, "receivers"));
      note = "baseline: per receiver; " + note +
             fmt(", %.1f far SLs per receiver", r.counter(c.key, "far_per_receiver").value_or(NAN));
    } else if (c.kind == "frame" && c.blocking == "per_object") {
      baseline = ms(frame_key(c.scene, "per_sphere", c.method));
      note = "baseline: per sphere; " + note;
    } else if (c.kind == "sweep" && !(c.method == "receivers" && c.min_sin == 0)) {
      baseline = ms(sweep_key(c.blocking, "receivers", 0.0f, 0));
      note = "baseline: per receiver, min_sin 0; " + note;
    }
    std::string name = std::string(c.kind == "frame" ? "frame " : "sweep ") + c.scene + " " +
                       c.blocking + " " + c.method + ", min_sin " + min_sin_text(c.min_sin);
    if (c.method == "clusters") name += ", far_ratio " + min_sin_text(c.far_ratio);
    add_row(s, name, "ms", ms(c.key), baseline,
            c.goal_ms ? pb::Goal::value_at_most(*c.goal_ms) : pb::Goal::none(), floor, note);
  }
  ps::write_records(r, ns_per_fma, out);
  return s;
}

}  // namespace

namespace penumbra::bench::spherical {

std::vector<FrameCaseInfo> frame_cases() {
  std::vector<FrameCaseInfo> out;
  for (const char* sc : {"squirrel:14", "objects:64"}) {
    const bool squirrel = std::string(sc) == "squirrel:14";
    for (const char* m : {"receivers", "clusters"})
      for (const char* b : kBlockings)
        out.push_back({frame_key(sc, b, m), "frame", sc, b, m, kDefaultMinSin,
                       std::string(m) == "clusters" ? kFarRatio : 0.0f,
                       squirrel ? 21'000.0 : 100'000.0, squirrel ? 14.0 : 64.0,
                       squirrel ? kGoalSquirrelMs : kGoalObjectsMs});
  }
  for (const char* b : kBlockings)
    for (const SweepCase& w : kSweep)
      out.push_back({sweep_key(b, w.method, w.min_sin, w.far_ratio), "sweep", "objects:64", b,
                     w.method, w.min_sin, w.far_ratio, 100'000.0, 64.0, std::nullopt});
  return out;
}

std::optional<double> frame_floor_ms(const Results& r, const std::string& key, double ns_per_fma) {
  const auto ops = r.counter(key, "ops_per_frame");
  if (!ops || !(ns_per_fma > 0)) return std::nullopt;
  return *ops * ns_per_fma / kThreads * 1e-6;
}

}  // namespace penumbra::bench::spherical

int main(int argc, char** argv) {
  ps::Outputs out;
  out.records_path = pb::take_flag(argc, argv, "records_out");
  out.chart_path = pb::take_flag(argc, argv, "chart_out");
  return pb::run_group(argc, argv, "spherical_lights", register_benchmarks,
                       [&](const pb::Results& r) { return summarize(r, out); });
}
