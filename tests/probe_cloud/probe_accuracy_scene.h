// The static scene of the probe-cloud accuracy tests (probe_accuracy_test.cpp) and of the
// `probes` benchmark group's speed-versus-accuracy records (tests/bench/probe_records.cpp):
// a ground plane, two boxes, a smooth sky with a broad bright lobe (no sun: the probes' SH are
// projected by stratified uniform directions), probe clouds (grids, random points, a hand-placed
// cloud), probe SH from the reference integrator and the interpolated irradiance's error against
// the reference irradiance at query points ([Cupisz12], [Ramamoorthi01]).
//
// Probe SH: the radiance the probe sees, L(w) V(p, w) (engine/reference: the environment
// sampler's radiance, Scene::occluded for V), projected on 4 bands with kProbeDirections
// stratified uniform directions, then convolved with the clamped cosine (sh::irradiance_convolve)
// and cut to the cloud's bands (or cut, then windowed against ringing: make_cloud's `dering`):
// E(n) = sum_i sh_i y_i(n), the data header's convention.
// Probes inside a box or on its walls are dropped (a baker would not place them there).
// Reference: reference::environment_irradiance (MIS) at each query point for the six axis
// normals.
// Threading: the functions are pure; the probe projection runs tbb::parallel_for.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "common/random_draws.h"
#include "penumbra/data/probe_cloud.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/convolution.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

namespace penumbra::probe_cloud::accuracy {

// Probe volume (metres): the clouds fill it; queries also go up to kMargin past it.
inline constexpr glm::vec3 kVolumeMin{0.0f, 0.0f, 0.25f};
inline constexpr glm::vec3 kVolumeMax{8.0f, 8.0f, 4.25f};
inline constexpr float kMargin = 1.5f;
inline constexpr float kEdgeBand = 0.5f;       // "edge" queries: this close to the volume's faces
inline constexpr int kProbeDirections = 2048;  // 32 x 64 strata (cos theta, phi)
// Probes within this of a box are dropped: on a wall, rays along it hit it (a baker would push
// them off; here the grids' lines x = 2, 4 and 6.5 m run along the walls).
inline constexpr float kSurfacePad = 0.02f;

struct Box {
  glm::vec3 lo, hi;
  bool contains(const glm::vec3& p, float pad = 0) const {
    return p.x > lo.x - pad && p.y > lo.y - pad && p.z > lo.z - pad && p.x < hi.x + pad &&
           p.y < hi.y + pad && p.z < hi.z + pad;
  }
};

inline const std::array<Box, 2>& boxes() {
  static const std::array<Box, 2> b{Box{{2.0f, 2.0f, 0.0f}, {4.0f, 4.0f, 2.0f}},
                                    Box{{5.0f, 4.5f, 0.0f}, {6.5f, 6.5f, 3.0f}}};
  return b;
}

inline bool in_box(const glm::vec3& p, float pad = 0) {
  for (const Box& b : boxes())
    if (b.contains(p, pad)) return true;
  return false;
}

inline glm::vec3 texel_direction(int x, int y, int w, int h) {
  const float phi = 2 * std::numbers::pi_v<float> * (x + 0.5f) / w;
  const float theta = std::numbers::pi_v<float> * (y + 0.5f) / h;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// An equirectangular map (penumbra/sh/projection.h layout) of radiance f(direction).
template <class F>
data::EnvironmentMap make_sky(F f, const std::string& name, int w = 128, int h = 64) {
  data::EnvironmentMap m;
  m.width = w;
  m.height = h;
  m.source = name;
  m.rgb.resize(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 c = f(texel_direction(x, y, w, h));
      float* t = m.rgb.data() + 3 * (static_cast<std::size_t>(y) * w + x);
      t[0] = c.x;
      t[1] = c.y;
      t[2] = c.z;
    }
  return m;
}

// A bluish gradient sky (brighter towards the zenith, dim below the horizon) and a broad warm
// lobe 35 degrees above the horizon towards +x, slightly +y: smooth, no sun.
inline data::EnvironmentMap lobe_sky() {
  const glm::vec3 lobe = glm::normalize(glm::vec3(0.8f, 0.25f, 0.6f));
  return make_sky(
      [&](const glm::vec3& d) {
        const float up = std::max(d.z, 0.0f);
        const float l = std::pow(std::max(glm::dot(d, lobe), 0.0f), 6.0f);
        return glm::vec3(0.25f, 0.35f, 0.5f) * (0.3f + up) + glm::vec3(3.0f, 2.6f, 2.0f) * l;
      },
      "lobe sky");
}

inline data::MeshData box_mesh(const Box& b) {
  data::MeshData m;
  m.name = "box";
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y,
                             i & 4 ? b.hi.z : b.lo.z);
  // 12 triangles (winding irrelevant: the reference's occluders are two-sided).
  const std::uint32_t q[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                 {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& f : q)
    for (std::uint32_t k : {f[0], f[1], f[2], f[0], f[2], f[3]}) m.indices.push_back(k);
  return m;
}

// Ground plane z = 0 (60 m x 60 m) and the boxes, lit by `sky`.
inline reference::Scene make_scene(const data::EnvironmentMap& sky, bool with_boxes = true) {
  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{sky, 0.0f};
  data::MeshData ground;
  ground.name = "ground";
  ground.positions = {{-26, -26, 0}, {34, -26, 0}, {34, 34, 0}, {-26, 34, 0}};
  ground.indices = {0, 1, 2, 0, 2, 3};
  desc.meshes.push_back({ground, glm::mat4(1.0f)});
  if (with_boxes)
    for (const Box& b : boxes()) desc.meshes.push_back({box_mesh(b), glm::mat4(1.0f)});
  return reference::Scene(desc);
}

// Radiance SH (4 bands, per channel) at each point: the projection of L V.
inline std::vector<sh::CoeffsRgb<4>> probe_radiance_sh(const reference::Scene& scene,
                                                       const std::vector<glm::vec3>& points,
                                                       int directions = kProbeDirections) {
  const int nu = std::max(1, static_cast<int>(std::sqrt(directions / 2.0))), nv = 2 * nu;
  const float weight = 4 * std::numbers::pi_v<float> / static_cast<float>(nu * nv);
  std::vector<sh::CoeffsRgb<4>> out(points.size());
  const reference::EnvironmentSampler* env = scene.environment();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        std::mt19937 rng(static_cast<std::uint32_t>(7919 * i + 13));
                        std::uniform_real_distribution<float> u(0, 1);
                        sh::CoeffsRgb<4> rad{};
                        for (int a = 0; a < nu; ++a)
                          for (int b = 0; b < nv; ++b) {
                            const float z = 1 - 2 * (a + u(rng)) / nu;
                            const float phi = 2 * std::numbers::pi_v<float> * (b + u(rng)) / nv;
                            const float s = std::sqrt(std::max(0.0f, 1 - z * z));
                            const glm::vec3 w(s * std::cos(phi), s * std::sin(phi), z);
                            if (scene.occluded(points[i], w, 1e4f)) continue;
                            const glm::vec3 l = env->lookup(w).radiance * weight;
                            const sh::Coeffs<4> y = sh::eval_basis<4>(w);
                            for (int c = 0; c < 3; ++c)
                              for (int k = 0; k < 16; ++k) rad[c][k] += l[c] * y[k];
                          }
                        out[i] = rad;
                      }
                    });
  return out;
}

// Irradiance SH (4 bands, per channel) at each point: the radiance's clamped cosine convolution.
inline std::vector<sh::CoeffsRgb<4>> probe_irradiance_sh(const reference::Scene& scene,
                                                         const std::vector<glm::vec3>& points,
                                                         int directions = kProbeDirections) {
  std::vector<sh::CoeffsRgb<4>> out = probe_radiance_sh(scene, points, directions);
  for (auto& probe : out)
    for (auto& c : probe) c = sh::irradiance_convolve<4>(c);
  return out;
}

// The irradiance of a 4-band radiance cut to B bands, windowed against ringing
// (sh::dering_irradiance: the weakest Hanning window that keeps it non-negative, [Sloan08]).
template <int B>
sh::Coeffs<4> dering_cut(const sh::Coeffs<4>& radiance) {
  sh::Coeffs<B> r{};
  for (int k = 0; k < B * B; ++k) r[k] = radiance[k];
  const sh::Coeffs<B> e = sh::dering_irradiance<B>(r);
  sh::Coeffs<4> out{};
  for (int k = 0; k < B * B; ++k) out[k] = e[k];
  return out;
}

// The cloud of `candidates` (those inside a box or on its surface dropped) with SH cut to `bands`;
// `dering`: each probe's irradiance windowed against ringing at that band count.
inline data::ProbeCloud make_cloud(const reference::Scene& scene,
                                   const std::vector<glm::vec3>& candidates, int bands,
                                   bool dering = false) {
  std::vector<glm::vec3> positions;
  for (const glm::vec3& p : candidates)
    if (!in_box(p, kSurfacePad)) positions.push_back(p);
  std::vector<sh::CoeffsRgb<4>> sh4;
  if (dering) {
    sh4 = probe_radiance_sh(scene, positions);
    for (auto& probe : sh4)
      for (auto& c : probe)
        c = bands == 2 ? dering_cut<2>(c) : bands == 3 ? dering_cut<3>(c) : dering_cut<4>(c);
  } else {
    sh4 = probe_irradiance_sh(scene, positions);
  }
  const int n = bands * bands;
  std::vector<float> sh;
  sh.reserve(positions.size() * 3 * n);
  for (const auto& probe : sh4)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < n; ++k) sh.push_back(probe[c][k]);
  ProbeCloudBuildSettings settings;
  settings.bands = bands;
  return build_probe_cloud(positions, sh, settings);
}

// A uniform grid over the volume at `spacing` metres (the volume's corners included).
inline std::vector<glm::vec3> grid_points(float spacing) {
  std::vector<glm::vec3> out;
  const glm::vec3 size = kVolumeMax - kVolumeMin;
  const int nx = static_cast<int>(std::lround(size.x / spacing)),
            ny = static_cast<int>(std::lround(size.y / spacing)),
            nz = static_cast<int>(std::lround(size.z / spacing));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        out.push_back(kVolumeMin + glm::vec3(i, j, k) * size / glm::vec3(nx, ny, nz));
  return out;
}

// `count` uniform random points in the volume.
inline std::vector<glm::vec3> random_points(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> x(kVolumeMin.x, kVolumeMax.x),
      y(kVolumeMin.y, kVolumeMax.y), z(kVolumeMin.z, kVolumeMax.z);
  std::vector<glm::vec3> out;
  for (int i = 0; i < count; ++i) out.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, x, y, z));
  return out;
}

// As an artist would place them: a coarse frame over the volume (2.67 m x 2.67 m x 4 m), and
// around each box a ring of probes 0.3 m off its walls at two heights (low and just above the
// top), plus one over the box's centre.
inline std::vector<glm::vec3> hand_placed_points() {
  std::vector<glm::vec3> out;
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 3; ++j)
      for (int i = 0; i <= 3; ++i)
        out.push_back(kVolumeMin + glm::vec3(i / 3.0f, j / 3.0f, k) * (kVolumeMax - kVolumeMin));
  for (const Box& b : boxes()) {
    const glm::vec3 lo = b.lo - glm::vec3(0.3f), hi = b.hi + glm::vec3(0.3f);
    const glm::vec3 mid = 0.5f * (lo + hi);
    for (float z : {0.4f, b.hi.z + 0.3f})
      for (const glm::vec2 xy :
           {glm::vec2(lo.x, lo.y), glm::vec2(mid.x, lo.y), glm::vec2(hi.x, lo.y),
            glm::vec2(hi.x, mid.y), glm::vec2(hi.x, hi.y), glm::vec2(mid.x, hi.y),
            glm::vec2(lo.x, hi.y), glm::vec2(lo.x, mid.y)})
        out.emplace_back(xy.x, xy.y, z);
    out.emplace_back(mid.x, mid.y, b.hi.z + 0.3f);
  }
  return out;
}

// --- Queries and errors ------------------------------------------------------------------------

inline const std::array<glm::vec3, 6>& axis_normals() {
  static const std::array<glm::vec3, 6> n{glm::vec3(0, 0, 1), glm::vec3(0, 0, -1),
                                          glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                          glm::vec3(0, 1, 0), glm::vec3(0, -1, 0)};
  return n;
}

struct Queries {
  std::vector<glm::vec3> points;  // not in a box (0.05 m pad), above the ground
  // Reference irradiance per point and axis normal (point-major), luminance, and its standard
  // error.
  std::vector<float> reference, std_error;
};

// `count` random points in the volume grown by kMargin (not below z = 0.1), outside the boxes,
// and their reference irradiance (`samples` per receiver).
inline Queries make_queries(const reference::Scene& scene, int count, int samples,
                            std::uint32_t seed) {
  Queries q;
  std::mt19937 rng(seed);
  const glm::vec3 lo = kVolumeMin - glm::vec3(kMargin), hi = kVolumeMax + glm::vec3(kMargin);
  std::uniform_real_distribution<float> x(lo.x, hi.x), y(lo.y, hi.y), z(0.1f, hi.z);
  while (static_cast<int>(q.points.size()) < count) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, x, y, z);
    if (!in_box(p, 0.05f)) q.points.push_back(p);
  }
  std::vector<reference::Receiver> receivers;
  for (const glm::vec3& p : q.points)
    for (const glm::vec3& n : axis_normals()) receivers.push_back({p, n});
  reference::IrradianceOptions o;
  o.samples = samples;
  o.seed = seed;
  for (const reference::RgbEstimate& e : reference::environment_irradiance(scene, receivers, o)) {
    q.reference.push_back(reference::luminance(e.mean));
    q.std_error.push_back(reference::luminance(e.std_error));
  }
  return q;
}

enum class Region { kInterior, kEdge, kOutside };  // of a query, by the cell the walk finds
inline constexpr const char* kRegionNames[3] = {"interior", "edge", "outside"};

struct ErrorStats {
  double rel_rms = 0, max_rel = 0;  // sqrt(sum d^2 / sum ref^2); max |d| / RMS(ref)
  double noise = 0;                 // the reference's own: RMS(std_error) / RMS(ref)
  int points = 0;
};

struct CloudErrors {
  std::array<ErrorStats, 3> region{};  // by Region
  ErrorStats all;
  std::size_t probes = 0, tetrahedra = 0;
};

// The interpolated irradiance (luminance) at point p for normal n.
inline float interpolated(const ProbeSh& s, const glm::vec3& n) {
  const glm::vec3 e(sh::evaluate<4>(s[0], n), sh::evaluate<4>(s[1], n), sh::evaluate<4>(s[2], n));
  return reference::luminance(e);
}

// Interpolated against reference at every query: outside = in an outer cell (past the hull);
// edge = in a tetrahedron with a hull face, or within kEdgeBand of the volume's faces; interior =
// the other inner tetrahedra.
inline CloudErrors cloud_errors(const data::ProbeCloud& cloud, const Queries& q) {
  const ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(cloud));
  struct Acc {
    double d2 = 0, r2 = 0, s2 = 0, max_d = 0;
    int n = 0, points = 0;
  };
  std::array<Acc, 4> acc{};  // 3 = all
  std::int32_t cell = kNoCell;
  for (std::size_t i = 0; i < q.points.size(); ++i) {
    const ProbeWalkResult r = walk.locate(q.points[i], cell);
    cell = r.cell;
    const glm::vec3& p = q.points[i];
    Region region = Region::kInterior;
    if (r.cell >= 0) {
      const data::ProbeCell& c = cloud.cells[static_cast<std::size_t>(r.cell)];
      if (c.outer()) {
        region = Region::kOutside;
      } else {
        const glm::vec3 lo = kVolumeMin + glm::vec3(kEdgeBand),
                        hi = kVolumeMax - glm::vec3(kEdgeBand);
        if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z)
          region = Region::kEdge;
        for (std::int32_t nb : c.neighbours)
          if (cloud.cells[static_cast<std::size_t>(nb)].outer()) region = Region::kEdge;
      }
    }
    const ProbeSh s = walk.interpolate(r);
    for (Acc* a : {&acc[static_cast<int>(region)], &acc[3]}) {
      ++a->points;
      for (std::size_t k = 0; k < 6; ++k) {
        const double ref = q.reference[6 * i + k], se = q.std_error[6 * i + k];
        const double d = interpolated(s, axis_normals()[k]) - ref;
        a->d2 += d * d;
        a->r2 += ref * ref;
        a->s2 += se * se;
        a->max_d = std::max(a->max_d, std::abs(d));
        ++a->n;
      }
    }
  }
  const auto stats = [](const Acc& a) {
    ErrorStats s;
    s.points = a.points;
    if (a.r2 <= 0) return s;
    s.rel_rms = std::sqrt(a.d2 / a.r2);
    s.max_rel = a.max_d / std::sqrt(a.r2 / a.n);
    s.noise = std::sqrt(a.s2 / a.r2);
    return s;
  };
  CloudErrors e;
  for (int k = 0; k < 3; ++k) e.region[k] = stats(acc[k]);
  e.all = stats(acc[3]);
  e.probes = cloud.probe_count();
  e.tetrahedra = cloud.inner_count;
  return e;
}

}  // namespace penumbra::probe_cloud::accuracy
