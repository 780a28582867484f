// Accuracy of the spherical lights ([Guerrero08] sec. 4-7, issue 13) against the reference
// integrator's one diffuse bounce (engine/reference: indirect_irradiance off the same meshes with
// the same albedo, under the same sky). Ours: sample_reflector -> ReflectorLighting (pass 1: the
// blocker system's BlockerAccumulation at the sample points, eq. 3-11) -> SphereLightGather
// (pass 2, eq. 14-24) for the indirect term; BlockerAccumulation::irradiance for the direct term.
// 4 bands throughout (the system's). No ground geometry in either: receivers "on the ground" are
// upward points at z = 0 whose horizon hides everything below ([Guerrero08] sec. 8: large flat
// surfaces receive but do not reflect).
//
// Errors, RGB together, over a scene's receivers: relative RMS sqrt(sum |E - E_ref|^2 /
// sum |E_ref|^2), max |E - E_ref| / RMS(E_ref), and the signed bias sum (E - E_ref) . 1 /
// sum E_ref . 1 (the tests/bench spherical_lights group's definitions). The reference's own
// noise on the same scale, sqrt(sum se^2 / sum |E_ref|^2), is printed beside each. Measured values
// are in comments and in docs/spherical_light_accuracy.md; bounds sit a little above them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "common/stability.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/sphere_fit.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/spherical_lights/reflector_lighting.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "test_meshes.h"

namespace penumbra::spherical_lights {
namespace {

namespace ba = blocker_accumulation;
namespace ref = reference;

constexpr int N = 4;
constexpr float kPi = 3.14159265358979f;
const std::filesystem::path kData = PENUMBRA_SHARED_DATA;

// Reference sampling: first-hit directions per receiver and direct samples per hit (indirect),
// directions per receiver (direct).
constexpr int kIndirectSamples = 16384;
constexpr int kBounceSamples = 8;
constexpr int kDirectSamples = 8192;

// --- Skies --------------------------------------------------------------------------------------

enum class Sky { kUniform, kLobe };

// Uniform: L = 1. Lobe: L = (1 + z)^2 / 2 (2 at the zenith, 1/2 at the horizon, 0 at the nadir):
// a degree-2 polynomial, so 3 SH bands hold it exactly and the sky itself adds no ringing.
glm::vec3 sky_radiance(Sky sky, const glm::vec3& d) {
  if (sky == Sky::kUniform) return glm::vec3(1.0f);
  return glm::vec3(0.5f * (1 + d.z) * (1 + d.z));
}

data::EnvironmentMap sky_map(Sky sky) {
  data::EnvironmentMap m;
  m.width = 128;
  m.height = 64;
  m.source = sky == Sky::kUniform ? "uniform sky" : "lobe sky";
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const glm::vec3 c =
          sky_radiance(sky, sh::equirect_direction((x + 0.5f) / m.width, (y + 0.5f) / m.height));
      m.rgb.insert(m.rgb.end(), {c.x, c.y, c.z});
    }
  return m;
}

sh::CoeffsRgb<N> sky_sh(Sky sky) {
  const data::EnvironmentMap m = sky_map(sky);
  return sh::project_equirect<N>(m.rgb.data(), m.width, m.height);
}

// --- Meshes (world frame, outward winding) -----------------------------------------------------

// A UV sphere: `stacks` rings from pole to pole, `slices` around; radial normals.
data::MeshData uv_sphere(glm::vec3 centre, float radius, int stacks = 32, int slices = 64) {
  data::MeshData m;
  m.name = "uv sphere";
  for (int i = 0; i <= stacks; ++i) {
    const float t = kPi * static_cast<float>(i) / stacks;
    for (int j = 0; j <= slices; ++j) {
      const float p = 2 * kPi * static_cast<float>(j) / slices;
      const glm::vec3 d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      m.positions.push_back(centre + radius * d);
      m.normals.push_back(d);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * (slices + 1) + j); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      // Counter-clockwise seen from outside (theta grows downwards, phi eastwards).
      if (i > 0) m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + 1 < stacks)
        m.indices.insert(m.indices.end(), {at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }
  return m;
}

// A prism: the counter-clockwise polygon `outline` in the xz plane (x, z), fanned from its first
// vertex (it must be star-shaped from there), extruded over y in [-half_y, half_y]. Flat normals.
data::MeshData prism(const std::vector<glm::vec2>& outline, float half_y) {
  data::MeshData m;
  m.name = "prism";
  const auto add = [&](glm::vec3 p, glm::vec3 n) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    return static_cast<std::uint32_t>(m.positions.size() - 1);
  };
  const std::size_t k = outline.size();
  // Caps: y = -half_y faces -y, y = +half_y faces +y. In (x, z) counter-clockwise is seen from
  // -y (x right, z up looking along +y), so the -y cap keeps the order and the +y cap flips it.
  for (int side = 0; side < 2; ++side) {
    const float y = side ? half_y : -half_y;
    const glm::vec3 n(0, side ? 1.0f : -1.0f, 0);
    std::vector<std::uint32_t> v;
    for (const glm::vec2& q : outline) v.push_back(add(glm::vec3(q.x, y, q.y), n));
    for (std::size_t i = 1; i + 1 < k; ++i) {
      if (side == 0)
        m.indices.insert(m.indices.end(), {v[0], v[i], v[i + 1]});
      else
        m.indices.insert(m.indices.end(), {v[0], v[i + 1], v[i]});
    }
  }
  for (std::size_t i = 0; i < k; ++i) {
    const glm::vec2 a = outline[i], b = outline[(i + 1) % k];
    const glm::vec2 e = b - a;
    const glm::vec3 n = glm::normalize(glm::vec3(e.y, 0, -e.x));  // outward for ccw
    const std::uint32_t a0 = add(glm::vec3(a.x, -half_y, a.y), n);
    const std::uint32_t b0 = add(glm::vec3(b.x, -half_y, b.y), n);
    const std::uint32_t b1 = add(glm::vec3(b.x, half_y, b.y), n);
    const std::uint32_t a1 = add(glm::vec3(a.x, half_y, a.y), n);
    m.indices.insert(m.indices.end(), {a0, b1, b0, a0, a1, b1});
  }
  return m;
}

// A cylinder along x over [-length / 2, length / 2], radius a, axis at height h, `rings` x
// `slices` quads on its side plus fanned end caps; smooth side normals.
data::MeshData cylinder(float length, float a, float h, int rings = 64, int slices = 32) {
  data::MeshData m;
  m.name = "cylinder";
  for (int i = 0; i <= rings; ++i) {
    const float x = -length / 2 + length * static_cast<float>(i) / rings;
    for (int j = 0; j < slices; ++j) {
      const float p = 2 * kPi * static_cast<float>(j) / slices;
      const glm::vec3 d(0, std::cos(p), std::sin(p));
      m.positions.push_back(glm::vec3(x, 0, h) + a * d);
      m.normals.push_back(d);
    }
  }
  const auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>(i * slices + (j % slices));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < slices; ++j)
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i + 1, j)});
  for (int side = 0; side < 2; ++side) {
    const float x = side ? length / 2 : -length / 2;
    const glm::vec3 n(side ? 1.0f : -1.0f, 0, 0);
    const auto c = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(glm::vec3(x, 0, h));
    m.normals.push_back(n);
    for (int j = 0; j < slices; ++j) {
      const float p = 2 * kPi * static_cast<float>(j) / slices;
      m.positions.push_back(glm::vec3(x, a * std::cos(p), h + a * std::sin(p)));
      m.normals.push_back(n);
    }
    for (int j = 0; j < slices; ++j) {
      const std::uint32_t u = c + 1 + static_cast<std::uint32_t>(j);
      const std::uint32_t w = c + 1 + static_cast<std::uint32_t>((j + 1) % slices);
      if (side)
        m.indices.insert(m.indices.end(), {c, u, w});
      else
        m.indices.insert(m.indices.end(), {c, w, u});
    }
  }
  return m;
}

std::vector<data::Sphere> fit(const data::MeshData& mesh, int count, double* er = nullptr) {
  assets::SphereFitOptions o;
  o.count = count;
  o.method = assets::SphereFitMethod::kVariational;
  o.seed = 1;
  o.surface_samples = 4096;
  o.volume_cells = 16384;
  o.eval_samples = 1 << 14;
  o.coverage_samples = 1 << 12;
  const assets::SphereFitResult r = assets::fit_spheres(mesh, o);
  if (er) *er = r.error.outside_volume_ratio;
  return r.spheres;
}

glm::vec3 face_normal(const data::MeshData& m, std::size_t t) {
  const glm::vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                  c = m.positions[m.indices[3 * t + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

// --- Receivers --------------------------------------------------------------------------------

struct Receivers {
  std::vector<glm::vec3> points, normals;
  void add(glm::vec3 p, glm::vec3 n) { points.push_back(p), normals.push_back(glm::normalize(n)); }
  std::size_t size() const { return points.size(); }
};

// Upward points on z = 0 over [lo, hi] (an nx x ny grid), those for which `keep` holds.
template <class Keep>
void add_ground(Receivers& r, glm::vec2 lo, glm::vec2 hi, int nx, int ny, Keep keep) {
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const glm::vec3 p(lo.x + (hi.x - lo.x) * (i + 0.5f) / nx,
                        lo.y + (hi.y - lo.y) * (j + 0.5f) / ny, 0.0f);
      if (keep(p)) r.add(p, glm::vec3(0, 0, 1));
    }
}

// `count` area-weighted points on `mesh` whose face normal passes `keep(p, n)`, 1 mm out along
// that normal (deterministic for `seed`).
template <class Keep>
void add_surface(Receivers& r, const data::MeshData& mesh, std::size_t count, std::uint32_t seed,
                 Keep keep) {
  std::vector<double> cdf;
  double total = 0;
  for (std::size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]],
                    b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    total += 0.5 * glm::length(glm::cross(b - a, c - a));
    cdf.push_back(total);
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (int tries = 0; r.size() < count && tries < 100000; ++tries) {
    const auto t = static_cast<std::size_t>(
        std::lower_bound(cdf.begin(), cdf.end(), u(rng) * total) - cdf.begin());
    if (t >= cdf.size()) continue;
    float s = static_cast<float>(u(rng)), w = static_cast<float>(u(rng));
    if (s + w > 1) s = 1 - s, w = 1 - w;
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]],
                    b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    const glm::vec3 n = face_normal(mesh, t);
    const glm::vec3 p = a + s * (b - a) + w * (c - a) + 1e-3f * n;
    if (keep(p, n)) r.add(p, n);
  }
}

// --- Ours ------------------------------------------------------------------------------------

// One reflecting object: its mesh (world frame) and albedo, its spheres, and per SL a pose
// (identity, except for the bend test: the SL's own rigid motion, [Guerrero08] sec. 7.1, fig. 9).
struct Object {
  data::MeshData mesh;  // the reference's geometry; mesh.base_color = albedo
  glm::vec3 albedo{0.5f};
  std::vector<data::Sphere> spheres;  // in the frame of `samples`
  ReflectorSamples samples;
  std::vector<ObjectPose> sl_pose;  // empty: identity for the whole object
};

Object make_object(data::MeshData mesh, glm::vec3 albedo, std::vector<data::Sphere> spheres) {
  Object o;
  o.albedo = albedo;
  mesh.base_color = glm::vec4(albedo, 1.0f);
  o.mesh = std::move(mesh);
  o.spheres = std::move(spheres);
  o.samples = sample_reflector(o.mesh, o.spheres);
  return o;
}

ObjectPose pose_of(const Object& o, std::size_t sl) {
  return o.sl_pose.empty() ? ObjectPose{} : o.sl_pose[sl];
}

struct Result {
  std::vector<glm::vec3> direct, indirect;
};

const ReflectorLighting<N>& lighting() {
  static const ReflectorLighting<N> l(geodesic_directions(3));
  return l;
}

Result ours(const std::vector<Object>& objects, Sky sky, const Receivers& rx, SlBlocking blocking,
            EmitterHorizon horizon = EmitterHorizon::kShrink) {
  const sh::CoeffsRgb<N> env = sky_sh(sky);
  std::vector<ba::WorldSphere> spheres;
  std::vector<ba::BlockerGroup> groups;
  for (const Object& o : objects) {
    const auto first = static_cast<std::uint32_t>(spheres.size());
    for (std::size_t k = 0; k < o.spheres.size(); ++k) {
      const ObjectPose p = pose_of(o, k);
      spheres.push_back({p.rotation * (p.scale * o.spheres[k].centre) + p.translation,
                         p.scale * o.spheres[k].radius});
    }
    groups.push_back(ba::bound_group(std::span(spheres).subspan(first), first));
  }
  ba::BlockerAccumulation<N> blockers;
  blockers.set_blockers(spheres, groups);
  std::vector<SphereLightSource<N>> lights;
  for (std::uint32_t id = 0; id < objects.size(); ++id) {
    const Object& o = objects[id];
    if (o.sl_pose.empty()) {
      const auto radiance = lighting().update(o.samples, {}, blockers, env);  // eq. 3-11
      ReflectorLighting<N>::place(o.samples, {}, radiance, id, lights);
      continue;
    }
    for (std::size_t k = 0; k < o.samples.lights.size(); ++k) {  // one rigid motion per SL
      ReflectorSamples one;
      one.directions = o.samples.directions;
      one.lights = {o.samples.lights[k]};
      const auto radiance = lighting().update(one, o.sl_pose[k], blockers, env);
      ReflectorLighting<N>::place(one, o.sl_pose[k], radiance, id, lights);  // one object id
    }
  }
  SphereLightSettings s;
  s.blocking = blocking;
  s.horizon = horizon;
  SphereLightGather<N> gather(s);
  gather.set_lights(lights);
  Result r;
  for (std::size_t i = 0; i < rx.size(); ++i) {
    r.indirect.push_back(gather.irradiance(rx.points[i], rx.normals[i]));
    r.direct.push_back(blockers.irradiance(env, rx.points[i], rx.normals[i]));
  }
  return r;
}

// --- Reference ---------------------------------------------------------------------------------

struct Reference {
  std::vector<ref::RgbEstimate> direct, indirect, total;
  double seconds = 0;
};

Reference reference_of(const ref::SceneDesc& desc, const Receivers& rx,
                       int indirect_samples = kIndirectSamples) {
  const auto t0 = std::chrono::steady_clock::now();
  const ref::Scene scene(desc);
  std::vector<ref::Receiver> receivers;
  for (std::size_t i = 0; i < rx.size(); ++i) receivers.push_back({rx.points[i], rx.normals[i]});
  ref::IrradianceOptions d;
  d.samples = kDirectSamples;
  d.seed = 3;
  ref::BounceOptions b;
  b.samples = indirect_samples;
  b.bounce_samples = kBounceSamples;
  b.seed = 5;
  Reference r;
  r.direct = ref::environment_irradiance(scene, receivers, d);
  r.indirect = ref::indirect_irradiance(scene, receivers, b);
  for (std::size_t i = 0; i < rx.size(); ++i)
    r.total.push_back(ref::combine(r.direct[i], r.indirect[i]));
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

ref::SceneDesc scene_of(const std::vector<Object>& objects, Sky sky) {
  ref::SceneDesc desc;
  desc.environment = ref::EnvironmentLight{sky_map(sky), 0.0f};
  for (const Object& o : objects) desc.meshes.push_back({o.mesh, glm::mat4(1.0f), o.albedo});
  return desc;
}

// --- Errors
// ---------------------------------------------------------------------------------------

struct Errors {
  double rms = 0, max = 0, bias = 0, ref_se = 0;  // relative (see the top)
  double ref_mean = 0;                            // mean |E_ref| (RGB length)
};

Errors compare(const std::vector<glm::vec3>& ours, const std::vector<ref::RgbEstimate>& ref,
               const std::vector<std::size_t>* subset = nullptr) {
  double d2 = 0, r2 = 0, se2 = 0, dmax = 0, dsum = 0, rsum = 0, rlen = 0;
  std::size_t n = 0;
  const auto one = [&](std::size_t i) {
    EXPECT_TRUE(std::isfinite(ours[i].x) && std::isfinite(ours[i].y) && std::isfinite(ours[i].z))
        << i;
    const glm::vec3 d = ours[i] - ref[i].mean;
    d2 += glm::dot(d, d);
    r2 += glm::dot(ref[i].mean, ref[i].mean);
    se2 += glm::dot(ref[i].std_error, ref[i].std_error);
    dmax = std::max(dmax, static_cast<double>(glm::length(d)));
    dsum += d.x + d.y + d.z;
    rsum += ref[i].mean.x + ref[i].mean.y + ref[i].mean.z;
    rlen += glm::length(ref[i].mean);
    ++n;
  };
  if (subset) {
    for (std::size_t i : *subset) one(i);
  } else {
    for (std::size_t i = 0; i < ours.size(); ++i) one(i);
  }
  Errors e;
  if (r2 <= 0 || n == 0) return e;
  e.rms = std::sqrt(d2 / r2);
  e.max = dmax / std::sqrt(r2 / static_cast<double>(n));
  e.bias = dsum / rsum;
  e.ref_se = std::sqrt(se2 / r2);
  e.ref_mean = rlen / static_cast<double>(n);
  return e;
}

std::vector<glm::vec3> sum(const Result& r) {
  std::vector<glm::vec3> t;
  for (std::size_t i = 0; i < r.direct.size(); ++i) t.push_back(r.direct[i] + r.indirect[i]);
  return t;
}

const char* mode_name(SlBlocking b) {
  return b == SlBlocking::kPerSphere ? "per sphere" : "per object";
}

struct Row {
  Errors indirect, total, direct;
};

// One table row: the scene, mode and SL count with the indirect and direct + indirect errors and
// the reference's noise, printed in the docs' table format.
Row report(const std::string& scene, SlBlocking mode, std::size_t sls, const Result& o,
           const Reference& r) {
  Row row{compare(o.indirect, r.indirect), compare(sum(o), r.total), compare(o.direct, r.direct)};
  std::printf(
      "| %s | %s | %zu | %zu | %.1f%% | %.1f%% | %+.1f%% | %.2f%% | %.1f%% | %.1f%% | %.2f%% | "
      "%.1f%% |\n",
      scene.c_str(), mode_name(mode), sls, o.indirect.size(), 100 * row.indirect.rms,
      100 * row.indirect.max, 100 * row.indirect.bias, 100 * row.indirect.ref_se,
      100 * row.total.rms, 100 * row.total.max, 100 * row.total.ref_se, 100 * row.direct.rms);
  std::printf("  (indirect / total mean |E_ref| %.4g / %.4g; reference %.2f s)\n",
              row.indirect.ref_mean, row.total.ref_mean, r.seconds);
  std::fflush(stdout);
  return row;
}

std::size_t sl_count(const std::vector<Object>& objects) {
  std::size_t n = 0;
  for (const Object& o : objects) n += o.spheres.size();
  return n;
}

// The reference's noise must sit well below what is measured.
void expect_quiet_reference(const Row& row) {
  EXPECT_LT(row.indirect.ref_se, 0.3 * row.indirect.rms);
  EXPECT_LT(row.total.ref_se, 0.3 * row.total.rms);
}

// --- 1. A sphere beside a plane ----------------------------------------------------------------
// [Guerrero08] fig. 8 row 1, "the optimal case": a UV sphere of radius 0.5 (2,048 triangles),
// 0.1 m above the ground, fitted with 1 sphere; 15 x 15 upward receivers over [-2.5, 2.5]^2.

TEST(SphericalLightAccuracy, SphereBesidePlane) {
  const data::MeshData mesh = uv_sphere(glm::vec3(0, 0, 0.6f), 0.5f);
  double er = 0;
  const std::vector<Object> objects = {
      make_object(mesh, glm::vec3(0.8f, 0.3f, 0.2f), fit(mesh, 1, &er))};
  Receivers rx;
  add_ground(rx, glm::vec2(-2.5f), glm::vec2(2.5f), 15, 15, [](glm::vec3) { return true; });
  std::printf("sphere: 1 SL, Er %.3f\n", er);
  for (Sky sky : {Sky::kUniform, Sky::kLobe}) {
    const Reference r = reference_of(scene_of(objects, sky), rx);
    const Result o = ours(objects, sky, rx, SlBlocking::kPerSphere);
    const Row row = report(sky == Sky::kUniform ? "sphere, uniform sky" : "sphere, lobe sky",
                           SlBlocking::kPerSphere, 1, o, r);
    // Measured, uniform sky: indirect 0.4% RMS (the reference's noise, 0.35%: the one SL is
    // exact here), total 1.2%; lobe sky: indirect 9.5% (bias -10%), total 1.4%.
    const bool uniform = sky == Sky::kUniform;
    if (!uniform) expect_quiet_reference(row);
    EXPECT_LT(row.indirect.rms, uniform ? 0.015 : 0.11);
    EXPECT_LT(row.total.rms, uniform ? 0.02 : 0.02);
  }
}

// --- 2. A cube with 1 and with 8 SLs ---------------------------------------------------------
// [Guerrero08] fig. 10: a unit cube on the ground; one SL blurs the bright-top / dark-bottom
// contrast of its faces and lights the ground near its edges too weakly, eight do better.
// Receivers: upward on the ground around it, 24 x 24 over [-2, 2]^2 less the footprint.

TEST(SphericalLightAccuracy, CubeWithOneAndEightSls) {
  const data::MeshData mesh =
      test::box_mesh(glm::vec3(-0.5f, -0.5f, 0.0f), glm::vec3(0.5f, 0.5f, 1.0f));
  Receivers rx;
  add_ground(rx, glm::vec2(-2.0f), glm::vec2(2.0f), 24, 24,
             [](glm::vec3 p) { return std::max(std::abs(p.x), std::abs(p.y)) > 0.52f; });
  const Reference r = reference_of(scene_of({make_object(mesh, glm::vec3(0.2f, 0.7f, 0.3f),
                                                         {{glm::vec3(0, 0, 0.5f), 0.87f, -1}})},
                                            Sky::kLobe),
                                   rx);
  for (int count : {1, 8}) {
    double er = 0;
    const std::vector<Object> objects = {
        make_object(mesh, glm::vec3(0.2f, 0.7f, 0.3f), fit(mesh, count, &er))};
    std::printf("cube: %d SLs, Er %.3f\n", count, er);
    for (SlBlocking mode : {SlBlocking::kPerSphere, SlBlocking::kPerObject}) {
      const Row row =
          report("cube", mode, objects[0].spheres.size(), ours(objects, Sky::kLobe, rx, mode), r);
      expect_quiet_reference(row);
      // Measured (either mode: one object, so the same order): 1 SL indirect 44.1% RMS (bias
      // -33%), total 1.0%; 8 SLs indirect 39.0% (bias -27%), total 2.3%.
      EXPECT_LT(row.indirect.rms, count == 1 ? 0.48 : 0.43);
      EXPECT_LT(row.total.rms, count == 1 ? 0.015 : 0.03);
    }
    // EmitterHorizon::kClip for the comparison in the docs (measured: 1 SL 44.0% RMS, bias +9%;
    // 8 SLs 32.8%, bias -3%): the shrink's bias at the horizon is gone.
    const Row clipped =
        report("cube, kClip", SlBlocking::kPerSphere, objects[0].spheres.size(),
               ours(objects, Sky::kLobe, rx, SlBlocking::kPerSphere, EmitterHorizon::kClip), r);
    EXPECT_GT(clipped.indirect.bias, -0.1);
  }
}

// --- 3. Two models close together --------------------------------------------------------------
// Bunny and Suzanne (../shared/data/models), each scaled to a bounding-box half-diagonal of
// 0.5 m, resting on the ground 0.02 m up, side by side along x with their fitted sphere sets
// 0.02 m apart ([Guerrero08] sec. 6.2: objects' SLs must not intersect). Receivers: 120 points on
// each model's side facing the other, and 15 x 10 upward points on the ground around them.

data::MeshData load_model(const std::string& file) {
  data::MeshData m = assets::merge_instances(assets::load_gltf(kData / "models" / file));
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const float scale = 1 / glm::length(hi - lo);
  const glm::vec3 centre = 0.5f * (lo + hi);
  for (glm::vec3& p : m.positions) {
    p = scale * (p - centre);
    p.z += scale * 0.5f * (hi.z - lo.z) + 0.02f;
  }
  m.normals = data::vertex_normals(m);  // uniform scale: the model's own normals still hold
  return m;
}

void translate(data::MeshData& m, std::vector<data::Sphere>& s, glm::vec3 t) {
  for (glm::vec3& p : m.positions) p += t;
  for (data::Sphere& x : s) x.centre += t;
}

TEST(SphericalLightAccuracy, TwoModelsCloseTogether) {
  for (int count : {8}) {
    data::MeshData bunny = load_model("bunny.glb"), suzi = load_model("suzi.glb");
    double er_b = 0, er_s = 0;
    std::vector<data::Sphere> sb = fit(bunny, count, &er_b), ss = fit(suzi, count, &er_s);
    // Bunny to the left of x = 0, Suzanne to the right, their sphere sets 0.02 m apart.
    float b_max = -1e9f, s_min = 1e9f;
    for (const data::Sphere& x : sb) b_max = std::max(b_max, x.centre.x + x.radius);
    for (const data::Sphere& x : ss) s_min = std::min(s_min, x.centre.x - x.radius);
    translate(bunny, sb, glm::vec3(-0.01f - b_max, 0, 0));
    translate(suzi, ss, glm::vec3(0.01f - s_min, 0, 0));
    std::vector<Object> objects = {make_object(bunny, glm::vec3(0.8f, 0.25f, 0.15f), sb),
                                   make_object(suzi, glm::vec3(0.2f, 0.35f, 0.85f), ss)};
    std::printf("bunny + suzanne: %d SLs each, Er %.3f / %.3f\n", count, er_b, er_s);
    Receivers rx;
    add_surface(rx, bunny, 120, 1, [](glm::vec3, glm::vec3 n) { return n.x > 0.3f; });
    add_surface(rx, suzi, 240, 2, [](glm::vec3, glm::vec3 n) { return n.x < -0.3f; });
    const std::size_t on_models = rx.size();
    add_ground(rx, glm::vec2(-2.0f, -1.5f), glm::vec2(2.0f, 1.5f), 15, 10,
               [](glm::vec3) { return true; });
    const Reference r = reference_of(scene_of(objects, Sky::kLobe), rx);
    std::vector<std::size_t> models, ground;
    for (std::size_t i = 0; i < rx.size(); ++i) (i < on_models ? models : ground).push_back(i);
    std::vector<std::vector<glm::vec3>> results;
    for (SlBlocking mode : {SlBlocking::kPerSphere, SlBlocking::kPerObject}) {
      const Result o = ours(objects, Sky::kLobe, rx, mode);
      const Row row = report("bunny + Suzanne", mode, sl_count(objects), o, r);
      const Errors m = compare(o.indirect, r.indirect, &models),
                   g = compare(o.indirect, r.indirect, &ground);
      std::printf(
          "  indirect on the models: rms %.1f%% bias %+.1f%%; on the ground: rms %.1f%% "
          "bias %+.1f%%\n",
          100 * m.rms, 100 * m.bias, 100 * g.rms, 100 * g.bias);
      expect_quiet_reference(row);
      // Measured (both modes): indirect 65.6% RMS (bias -37%; on the models -43%, on the ground
      // +5%), total 10.1% (direct alone 9.5%: the spheres' outside volume shadows the models).
      // kClip gave 64.0% (bias -33%; models -39%, ground +9%).
      EXPECT_LT(row.indirect.rms, 0.70);
      EXPECT_LT(row.total.rms, 0.115);
      results.push_back(o.indirect);
    }
    double mode_diff = 0;
    for (std::size_t i = 0; i < rx.size(); ++i)
      mode_diff =
          std::max(mode_diff, static_cast<double>(glm::length(results[0][i] - results[1][i])));
    std::printf("  per sphere vs per object: largest indirect difference %.3g\n", mode_diff);
  }
}

// --- 4. [Guerrero08]'s own error sources -------------------------------------------------------

// (a) Crevice darkening from outside volume ([Guerrero08] sec. 8.2, fig. 8 row 3: "the darkening
// of crevices we can observe on the squirrel model", from the SL set's larger volume). An L-shaped
// prism (arms 2 m long, 0.5 m thick, 1.5 m deep) lying on the ground, fitted with 4 and 8
// spheres; receivers on its inner floor and inner wall along 3 lines across its depth. Crevice:
// within 0.5 m of the inner corner; open: farther than 1 m.
TEST(SphericalLightErrorSources, CreviceDarkeningFromOutsideVolume) {
  PENUMBRA_STABILITY("a crevice of an object fitted with 4 or 8 spheres",
                     "the SL set's larger volume darkens the crevice ([Guerrero08] sec. 8.2)",
                     "more spheres per object (8: less bias)");
  const data::MeshData mesh =
      prism({{0, 0}, {2, 0}, {2, 0.5f}, {0.5f, 0.5f}, {0.5f, 2}, {0, 2}}, 0.75f);
  Receivers rx;
  std::vector<std::size_t> crevice, open;
  for (float y : {-0.4f, 0.0f, 0.4f})
    for (int k = 0; k < 15; ++k) {
      const float t = 0.05f + 0.1f * static_cast<float>(k);  // distance from the corner
      for (int wall = 0; wall < 2; ++wall) {
        if (t < 0.5f) crevice.push_back(rx.size());
        if (t > 1.0f) open.push_back(rx.size());
        if (wall)
          rx.add(glm::vec3(0.501f, y, 0.5f + t), glm::vec3(1, 0, 0));
        else
          rx.add(glm::vec3(0.5f + t, y, 0.501f), glm::vec3(0, 0, 1));
      }
    }
  const glm::vec3 albedo(0.7f);
  const Reference r = reference_of(
      scene_of({make_object(mesh, albedo, {{glm::vec3(1), 2.0f, -1}})}, Sky::kLobe), rx);
  for (int count : {4, 8}) {
    double er = 0;
    const std::vector<Object> objects = {make_object(mesh, albedo, fit(mesh, count, &er))};
    const Result o = ours(objects, Sky::kLobe, rx, SlBlocking::kPerSphere);
    const std::vector<glm::vec3> total = sum(o);
    const Errors tc = compare(total, r.total, &crevice), to = compare(total, r.total, &open);
    const Errors dc = compare(o.direct, r.direct, &crevice),
                 dopen = compare(o.direct, r.direct, &open);
    const Errors ic = compare(o.indirect, r.indirect, &crevice),
                 io = compare(o.indirect, r.indirect, &open);
    std::printf(
        "crevice, %d SLs (Er %.2f): total bias crevice %+.1f%% open %+.1f%% (ref se %.2f%%); "
        "direct %+.1f%% / %+.1f%%; indirect %+.1f%% / %+.1f%% (ref se %.2f%%)\n",
        count, er, 100 * tc.bias, 100 * to.bias, 100 * tc.ref_se, 100 * dc.bias, 100 * dopen.bias,
        100 * ic.bias, 100 * io.bias, 100 * ic.ref_se);
    // Measured: 4 SLs (Er 3.0) total bias -48.5% in the crevice, -15.2% in the open (direct
    // -38.9% / -15.2%, indirect -85.4% / -14.3%); 8 SLs (Er 1.6) -35.4% / -12.6% (direct
    // -23.7% / -11.5%, indirect -79.7% / -30.6%); the reference's noise 0.15% (total).
    PENUMBRA_STABILITY_MEASURE("crevice bias, " + std::to_string(count) + " SLs", tc.bias);
    EXPECT_LT(tc.bias, to.bias - (count == 4 ? 0.28 : 0.18));  // darker in the crevice
    EXPECT_GT(tc.bias, count == 4 ? -0.55 : -0.42);
  }
}

// (b) Brightening where SLs intersect ([Guerrero08] sec. 8.1, fig. 7): two spheres of radius 0.5,
// centres 0.6 m apart on the x axis 1 m up (one object; the mesh is both UV spheres less the
// triangles inside the other; the reference has the exact union, two analytic spheres). Each SL's
// directions into the other emit nothing (sec. 4.2 rule 2, sec. 6.2) and intersecting SLs do not
// block each other at run time. Receivers facing the pair at 1.5-3 m from its middle: end-on (on
// the x axis, the SLs one behind the other, fig. 7 right) and side-on (on the y axis, side by
// side, fig. 7 left); the signed indirect bias of each.
TEST(SphericalLightErrorSources, BrighteningWhereSlsIntersect) {
  PENUMBRA_STABILITY("SLs intersecting (a cylinder seen end-on)",
                     "too bright where they overlap (measured +9.9% end-on, -1.0% side-on)", "-");
  const glm::vec3 a(-0.3f, 0, 1), b(0.3f, 0, 1);
  const float radius = 0.5f;
  data::MeshData mesh = uv_sphere(a, radius);
  const data::MeshData other = uv_sphere(b, radius);
  const auto inside = [&](const data::MeshData& m, std::size_t t, glm::vec3 c) {
    const glm::vec3 g = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                         m.positions[m.indices[3 * t + 2]]) /
                        3.0f;
    return glm::length(g - c) < radius;
  };
  std::vector<std::uint32_t> kept;
  for (std::size_t t = 0; t < mesh.indices.size() / 3; ++t)
    if (!inside(mesh, t, b))
      kept.insert(kept.end(), mesh.indices.begin() + 3 * t, mesh.indices.begin() + 3 * t + 3);
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (std::size_t t = 0; t < other.indices.size() / 3; ++t)
    if (!inside(other, t, a))
      for (int k = 0; k < 3; ++k) kept.push_back(base + other.indices[3 * t + k]);
  mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
  mesh.normals.insert(mesh.normals.end(), other.normals.begin(), other.normals.end());
  mesh.indices = kept;
  const glm::vec3 albedo(0.8f, 0.6f, 0.3f);
  const std::vector<Object> objects = {
      make_object(mesh, albedo, {{a, radius * 1.001f, -1}, {b, radius * 1.001f, -1}})};
  Receivers rx;
  std::vector<std::size_t> end_on, side_on;
  for (int k = 0; k < 7; ++k) {
    const float d = 1.5f + 0.25f * static_cast<float>(k);
    for (float s : {-1.0f, 1.0f}) {
      end_on.push_back(rx.size());
      rx.add(glm::vec3(s * d, 0, 1), glm::vec3(-s, 0, 0));
      side_on.push_back(rx.size());
      rx.add(glm::vec3(0, s * d, 1), glm::vec3(0, -s, 0));
    }
  }
  ref::SceneDesc desc;
  desc.environment = ref::EnvironmentLight{sky_map(Sky::kLobe), 0.0f};
  desc.spheres = {{a, radius, "a", albedo}, {b, radius, "b", albedo}};
  const Reference r = reference_of(desc, rx);
  const Result o = ours(objects, Sky::kLobe, rx, SlBlocking::kPerSphere);
  const Errors e = compare(o.indirect, r.indirect, &end_on),
               s = compare(o.indirect, r.indirect, &side_on);
  std::printf(
      "intersecting SLs: indirect bias end-on %+.1f%% (rms %.1f%%), side-on %+.1f%% "
      "(rms %.1f%%); ref se %.2f%% / %.2f%%\n",
      100 * e.bias, 100 * e.rms, 100 * s.bias, 100 * s.rms, 100 * e.ref_se, 100 * s.ref_se);
  // Measured: end-on +9.9% (RMS 8.8%), side-on -1.0% (RMS 1.1%), reference noise 0.7%.
  PENUMBRA_STABILITY_MEASURE("bias end-on", e.bias);
  PENUMBRA_STABILITY_MEASURE("bias side-on", s.bias);
  EXPECT_GT(e.bias - s.bias, 0.08);
  EXPECT_LT(e.bias, 0.13);
}

// (c) Weaker light at grazing angles from shrinking at the horizon ([Guerrero08] sec. 8.1, sec.
// 6.2 "receiver points inside SLs": an SL crossing the receiver's tangent plane is scaled down
// and moved above it). One sphere of radius 0.5 under the uniform sky: every point of it sees a
// whole hemisphere of sky, so its radiance is exactly albedo x 1, its one SL's SH is exact and
// every error is the receiver side's. Receivers 1 m from its centre (sin theta = 1/2), the normal
// tilted beta from the direction to the centre, beta = 0..115 degrees; the cap crosses the
// horizon from beta = 60 degrees on. Exact: albedo x the sphere's form factor x pi (Snyder's
// closed form, as tests/reference/bounce_test.cpp), checked by the reference.
double sphere_irradiance(double cos_theta, double sin2_sigma) {
  if (cos_theta * cos_theta > sin2_sigma) return kPi * sin2_sigma * std::max(0.0, cos_theta);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  const double x = std::sqrt(1 / sin2_sigma - 1);
  const double y = -x * cos_theta / sin_theta;
  const double s = sin_theta * std::sqrt(std::max(0.0, 1 - y * y));
  return std::max(0.0, (cos_theta * std::acos(y) - x * s) * sin2_sigma + std::atan(s / x));
}

TEST(SphericalLightErrorSources, WeakerLightAtGrazingAngles) {
  PENUMBRA_STABILITY("an SL crossing the receiver's horizon (grazing angles)",
                     "kShrink: the light falls to 0.25 of exact at 90 deg, 0 from 110 deg",
                     "EmitterHorizon::kClip: within 1% of exact");
  const glm::vec3 c(0, 0, 0);
  const float albedo = 0.5f;
  const std::vector<Object> objects = {
      make_object(uv_sphere(c, 0.5f, 64, 128), glm::vec3(albedo), {{c, 0.5005f, -1}})};
  Receivers rx;
  std::vector<double> beta;
  for (int k = 0; k <= 23; ++k) {
    const double b = 5.0 * k * kPi / 180;
    beta.push_back(b);
    // Receiver at (1, 0, 0); the direction to the centre is -x, tilted about z by beta.
    rx.add(glm::vec3(1, 0, 0), glm::vec3(-std::cos(b), std::sin(b), 0));
  }
  const Reference r = reference_of(scene_of(objects, Sky::kUniform), rx);
  // [Guerrero08] sec. 6.2's shrink (EmitterHorizon::kShrink, the default) and ours, the whole
  // sphere clipped by the horizon (kClip).
  const Result shrink = ours(objects, Sky::kUniform, rx, SlBlocking::kPerSphere);
  const Result clip =
      ours(objects, Sky::kUniform, rx, SlBlocking::kPerSphere, EmitterHorizon::kClip);
  double worst = 0, worst_beta = 0, inside_max = 0, clip_max = 0;
  for (std::size_t i = 0; i < rx.size(); ++i) {
    const double exact = albedo * sphere_irradiance(std::cos(beta[i]), 0.25);
    const double ratio = exact > 0 ? shrink.indirect[i].x / exact : 1.0;
    const double ratio_clip = exact > 0 ? clip.indirect[i].x / exact : 1.0;
    std::printf(
        "  beta %3.0f: shrink %.4f clip %.4f exact %.4f ref %.4f +- %.4f ratio %.3f / %.3f\n",
        beta[i] * 180 / kPi, shrink.indirect[i].x, clip.indirect[i].x, exact, r.indirect[i].mean.x,
        r.indirect[i].std_error.x, ratio, ratio_clip);
    EXPECT_NEAR(r.indirect[i].mean.x, exact, 4 * r.indirect[i].std_error.x + 1e-3 * exact) << i;
    if (exact > 1e-3) clip_max = std::max(clip_max, std::abs(ratio_clip - 1));
    if (beta[i] < kPi / 3 - 1e-3)
      inside_max = std::max(inside_max, std::abs(ratio - 1));
    else if (exact > 1e-3 && ratio - 1 < worst)
      worst = ratio - 1, worst_beta = beta[i];
  }
  std::printf(
      "grazing: kShrink above the horizon max |ratio - 1| %.2f%%, crossing it worst %+.1f%% at "
      "beta %.0f deg; kClip max |ratio - 1| %.2f%% at every angle\n",
      100 * inside_max, 100 * worst, worst_beta * 180 / kPi, 100 * clip_max);
  // Measured (kShrink): above the horizon (beta < 60 deg) within 0.33% of exact; crossing it the
  // light falls to 0.87 of exact at 65 deg, 0.47 at 80, 0.25 at 90, 0.10 at 100 and 0 from
  // 110 on (exact 0.0034 there): far more than [Guerrero08] sec. 8.1's "very small" (the plane
  // rule's shrink before the exact, horizon-clipped cap integral). kClip: within 1.0% of
  // exact wherever exact > 1e-3 (0.3% facing it): the table's eq. 16 weight and interpolation.
  PENUMBRA_STABILITY_MEASURE("kShrink worst relative error", worst);
  PENUMBRA_STABILITY_MEASURE("kClip max relative error", clip_max);
  EXPECT_LT(inside_max, 0.01);
  EXPECT_LT(worst, -0.9);
  EXPECT_LT(clip_max, 0.03);
}

// (d) Banding at a 180-degree bend ([Guerrero08] sec. 8.2, fig. 9): a cylinder (radius 0.25 m,
// 4 m long, axis 0.6 m up) with 8 SLs (each bounding a 0.5 m slice), bent into a U whose bottom
// faces the ground (outer side stretched). As in [Guerrero08] sec. 7.1 each SL moves rigidly with
// the bend at its centre ("the average transformation of all its associated vertices"); its
// sample points and emission-free directions come from the straight cylinder. The reference has
// the bent mesh. Receivers: upward, every 5 cm on the ground along the axis (x in [-1.5, 1.5]).
// Banding: the spread (max - min) of the signed indirect error along that line, relative to the
// line's mean reference indirect irradiance, straight and bent.
TEST(SphericalLightErrorSources, BandingAtA180DegreeBend) {
  PENUMBRA_STABILITY("an object bent 180 degrees",
                     "banding: the error's spread along a line grows (14.7% straight, 35.3% bent)",
                     "-");
  const float length = 4, a = 0.25f, h = 0.6f;
  const int sls = 8;
  const data::MeshData straight = cylinder(length, a, h, 128, 32);
  std::vector<data::Sphere> spheres;
  const float slice = length / sls;
  for (int k = 0; k < sls; ++k)
    spheres.push_back({glm::vec3(-length / 2 + slice * (k + 0.5f), 0, h),
                       1.001f * std::sqrt(a * a + 0.25f * slice * slice), -1});
  const float bend_radius = length / kPi;  // 180 degrees over the length
  const auto bend_at = [&](float x) {      // the rigid motion at axis abscissa x
    const float phi = x / bend_radius;
    ObjectPose p;
    p.rotation = glm::mat3(glm::vec3(std::cos(phi), 0, std::sin(phi)), glm::vec3(0, 1, 0),
                           glm::vec3(-std::sin(phi), 0, std::cos(phi)));
    const glm::vec3 axis(bend_radius * std::sin(phi), 0, h + bend_radius * (1 - std::cos(phi)));
    p.translation = axis - p.rotation * glm::vec3(x, 0, h);
    return p;
  };
  Receivers rx;
  for (int k = 0; k <= 60; ++k) rx.add(glm::vec3(-1.5f + 0.05f * k, 0, 0), glm::vec3(0, 0, 1));
  const glm::vec3 albedo(0.8f);
  double spread[2] = {0, 0};
  for (int bent = 0; bent < 2; ++bent) {
    Object o = make_object(straight, albedo, spheres);
    if (bent) {
      for (glm::vec3& p : o.mesh.positions) {
        const ObjectPose m = bend_at(p.x);
        p = m.rotation * p + m.translation;
      }
      for (const data::Sphere& s : spheres) o.sl_pose.push_back(bend_at(s.centre.x));
    }
    const std::vector<Object> objects = {o};
    const Reference r = reference_of(scene_of(objects, Sky::kUniform), rx);
    const Result ours_r = ours(objects, Sky::kUniform, rx, SlBlocking::kPerSphere);
    const Errors e = compare(ours_r.indirect, r.indirect);
    double lo = 1e9, hi = -1e9, mean = 0;
    for (std::size_t i = 0; i < rx.size(); ++i) mean += r.indirect[i].mean.x / rx.size();
    for (std::size_t i = 0; i < rx.size(); ++i) {
      const double d = (ours_r.indirect[i].x - r.indirect[i].mean.x) / mean;
      lo = std::min(lo, d), hi = std::max(hi, d);
      std::printf("    x %+.2f ours %.4f ref %.4f +- %.4f (%+.1f%%)\n", rx.points[i].x,
                  ours_r.indirect[i].x, r.indirect[i].mean.x, r.indirect[i].std_error.x, 100 * d);
    }
    spread[bent] = hi - lo;
    std::printf(
        "bend %d deg: indirect rms %.1f%% bias %+.1f%%, spread along the line %.1f%% "
        "(%+.1f%% .. %+.1f%%), ref se %.2f%%\n",
        bent ? 180 : 0, 100 * e.rms, 100 * e.bias, 100 * (hi - lo), 100 * lo, 100 * hi,
        100 * e.ref_se);
  }
  // Measured: straight, the error along the line spans +28.9% .. +43.6% (spread 14.7%, bias
  // +39%); bent 180 degrees, +10.3% .. +45.6% (spread 35.3%, bias +25%); reference noise 0.2%.
  // (Before sample_reflector's rays hit both triangles of a shared edge, the cylinder's rays
  // along its mesh edges found no point and those directions emitted nothing: +17% / +7.8%.)
  PENUMBRA_STABILITY_MEASURE("error spread, straight", spread[0]);
  PENUMBRA_STABILITY_MEASURE("error spread, bent", spread[1]);
  EXPECT_GT(spread[1], spread[0] + 0.1);
  EXPECT_LT(spread[1], 0.42);
}

}  // namespace
}  // namespace penumbra::spherical_lights
