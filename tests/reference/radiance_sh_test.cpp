// radiance_sh (radiance_sh.h): analytic cases (uniform sky, a reflecting plane, a light), back
// faces, determinism across thread counts, input errors.
#include "penumbra/reference/radiance_sh.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "common/stability.h"
#include "penumbra/sh/basis.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

using test::constant_map;
using test::quad;

// The SH projection of f over the sphere by a midpoint rule in (z, phi): exact reference values.
template <int N>
sh::Coeffs<N> quadrature(const std::function<double(const glm::vec3&)>& f, int m = 400) {
  std::array<double, N * N> acc{};
  for (int i = 0; i < m; ++i) {
    const double z = 1 - 2 * (i + 0.5) / m, r = std::sqrt(1 - z * z);
    for (int j = 0; j < 2 * m; ++j) {
      const double phi = 2 * std::numbers::pi * (j + 0.5) / (2 * m);
      const glm::vec3 d(r * std::cos(phi), r * std::sin(phi), z);
      const double v = f(d);
      if (v == 0) continue;
      const sh::Coeffs<N> y = sh::eval_basis<N>(d);
      for (int k = 0; k < N * N; ++k) acc[k] += v * y[k];
    }
  }
  sh::Coeffs<N> out{};
  const double dw = 4 * std::numbers::pi / (2.0 * m * m);
  for (int k = 0; k < N * N; ++k) out[k] = static_cast<float>(acc[k] * dw);
  return out;
}

TEST(RadianceSh, UniformSkyGivesDcOnly) {
  SceneDesc d;
  d.environment = EnvironmentLight{constant_map(64, 32, glm::vec3(2.0f, 1.0f, 0.5f))};
  const Scene scene(d);
  const std::vector<glm::vec3> p = {{0, 0, 0}, {10, -3, 7}};
  RadianceShOptions o;
  o.samples = 256;
  const auto e = radiance_sh<3>(scene, p, o);
  const float l[3] = {2.0f, 1.0f, 0.5f};
  for (const auto& r : e) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(r.mean[c][0], l[c] * std::sqrt(4 * std::numbers::pi), 1e-4 * l[c]);
      // Higher coefficients: zero to the estimate's own error bar.
      for (int i = 1; i < 9; ++i)
        EXPECT_LE(std::fabs(r.mean[c][i]), 4 * r.std_error[c][i] + 1e-5f) << i;
    }
    EXPECT_EQ(r.hits, 0u);
    EXPECT_EQ(r.samples, 256u);
  }
}

// A uniform sky of radiance 1 and a 4 km plane of albedo (0.5, 0.25, 0.8) 1 m above the origin.
constexpr glm::vec3 kPlaneAlbedo(0.5f, 0.25f, 0.8f);
SceneDesc albedo_plane_scene() {
  SceneDesc d;
  d.environment = EnvironmentLight{constant_map(64, 32, glm::vec3(1.0f))};
  MeshInstance plane{quad(2000.0f, 1.0f)};
  plane.albedo = kPlaneAlbedo;
  d.meshes.push_back(plane);
  return d;
}

// Every coefficient of `e` against the projection of a above and `below` under the plane, to
// four standard errors.
void expect_plane_radiance(const RadianceShEstimate<3>& e, double below) {
  for (int c = 0; c < 3; ++c) {
    const double a = kPlaneAlbedo[c];
    const sh::Coeffs<3> exact =
        quadrature<3>([a, below](const glm::vec3& w) { return w.z > 0 ? a : below; });
    for (int i = 0; i < 9; ++i)
      EXPECT_LE(std::fabs(e.mean[c][i] - exact[i]), 4 * e.std_error[c][i] + 2e-3)
          << "channel " << c << " coefficient " << i << " estimate " << e.mean[c][i] << " exact "
          << exact[i] << " std error " << e.std_error[c][i];
  }
}

// A probe 1 m under a 4 km plane of albedo a under a uniform sky L: the plane's underside sees
// the lower sky (E = pi L), so L_1 = a L above and L below (the plane's missing rim: < 1e-6 sr).
TEST(RadianceSh, UnderAnAlbedoPlane) {
  const Scene scene(albedo_plane_scene());
  const std::vector<glm::vec3> p = {{0, 0, 0}};
  RadianceShOptions o;
  o.samples = 2048;
  const auto e = radiance_sh<3>(scene, p, o)[0];
  expect_plane_radiance(e, 1.0);
  EXPECT_GE(e.dof, 30u);
  EXPECT_GT(e.hits, 900u);
  EXPECT_GT(e.rays, e.samples);
}

// The bounce alone (direct off, the bake's light decoupling): under the same plane only its
// reflection remains, a L above and nothing below; a light the probe sees directly adds nothing
// (no occluder reflects it), and fewer rays are cast than by the full capture.
TEST(RadianceSh, BounceAloneLeavesOnlyTheReflection) {
  const Scene scene(albedo_plane_scene());
  const std::vector<glm::vec3> p = {{0, 0, 0}};
  RadianceShOptions o;
  o.samples = 2048;
  const auto full = radiance_sh<3>(scene, p, o)[0];
  o.direct = false;
  const auto e = radiance_sh<3>(scene, p, o)[0];
  expect_plane_radiance(e, 0.0);
  EXPECT_LT(e.rays, full.rays);
  // A light in the open: nothing reflects it, so nothing arrives.
  SceneDesc dl;
  dl.lights.push_back({glm::vec3(0, 0, 3), 1.0f, glm::vec3(5.0f), "l"});
  const auto lit = radiance_sh<2>(Scene(dl), p, o)[0];
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 4; ++i) EXPECT_EQ(lit.mean[c][i], 0.0f);
}

// One spherical light, nothing else: the radiance is L inside its cone.
TEST(RadianceSh, SphericalLightCone) {
  SceneDesc d;
  d.lights.push_back({glm::vec3(0, 0, 3), 1.0f, glm::vec3(5.0f), "l"});
  const Scene scene(d);
  const std::vector<glm::vec3> p = {{0, 0, 0}};
  RadianceShOptions o;
  o.samples = 1024;
  const auto e = radiance_sh<3>(scene, p, o)[0];
  const double cos_max = std::sqrt(1 - 1.0 / 9.0);
  // Zonal: only m = 0 terms, 2 pi int_{cos_max}^1 y_l0(z) dz by a fine midpoint rule.
  sh::Coeffs<3> exact{};
  const int m = 200000;
  for (int k = 0; k < m; ++k) {
    const double z = cos_max + (1 - cos_max) * (k + 0.5) / m;
    const sh::Coeffs<3> y =
        sh::eval_basis<3>(glm::vec3(static_cast<float>(std::sqrt(1 - z * z)), 0.0f, float(z)));
    for (int i : {0, 2, 6})
      exact[i] += static_cast<float>(5.0 * 2 * std::numbers::pi * y[i] * (1 - cos_max) / m);
  }
  for (int i = 0; i < 9; ++i)
    EXPECT_LE(std::fabs(e.mean[0][i] - exact[i]),
              4 * e.std_error[0][i] + 5e-3 * std::fabs(exact[0]))
        << i << " " << e.mean[0][i] << " " << exact[i];
  // Inside the light: nothing from it.
  const std::vector<glm::vec3> inside = {{0, 0, 3.5f}};
  const auto z = radiance_sh<2>(scene, inside, o)[0];
  EXPECT_EQ(z.mean[0][0], 0.0f);
}

// A closed unit cube; a probe inside: every ray hits a back face, the estimate is 0 and the
// escape direction points to the nearest face.
TEST(RadianceSh, BackFacesInsideABox) {
  PENUMBRA_STABILITY(
      "a probe inside a closed box",
      "every ray hits a back face: zero estimate, the escape direction to the nearest face", "-");
  data::MeshData cube;
  cube.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  cube.indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                  1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  SceneDesc d;
  d.environment = EnvironmentLight{constant_map(32, 16, glm::vec3(1.0f))};
  d.meshes.push_back({cube, glm::mat4(1.0f), glm::vec3(0.5f)});
  const Scene scene(d);
  RadianceShOptions o;
  o.samples = 256;
  o.back_face = [](const glm::vec3& origin, const glm::vec3& dir, const Hit& h) {
    const glm::vec3 q = origin + (h.distance * 0.999f) * dir;
    return q.x > 0 && q.x < 1 && q.y > 0 && q.y < 1 && q.z > 0 && q.z < 1;
  };
  const std::vector<glm::vec3> p = {{0.5f, 0.5f, 0.9f}, {0.5f, 0.5f, 1.5f}};
  const auto e = radiance_sh<3>(scene, p, o);
  EXPECT_EQ(e[0].back_face_hits, e[0].samples);
  EXPECT_FLOAT_EQ(e[0].back_face_share(), 1.0f);
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 9; ++i) EXPECT_EQ(e[0].mean[c][i], 0.0f);
  EXPECT_GT(e[0].escape_dir.z, 0.9f);
  EXPECT_NEAR(e[0].escape_distance, 0.1f, 0.02f);
  // Above the box: no back faces, lit.
  EXPECT_EQ(e[1].back_face_hits, 0u);
  EXPECT_GT(e[1].hits, 0u);
  EXPECT_GT(e[1].mean[0][0], 0.0f);
}

TEST(RadianceSh, DeterministicAcrossThreadCounts) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::cosine_sky_map(64, 32)};
  MeshInstance plane{quad(5.0f, 0.0f)};
  plane.albedo = glm::vec3(0.7f);
  d.meshes.push_back(plane);
  d.lights.push_back({glm::vec3(2, 0, 2), 0.3f, glm::vec3(10.0f), "l"});
  const Scene scene(d);
  std::vector<glm::vec3> p;
  for (int i = 0; i < 64; ++i) p.emplace_back(0.1f * i - 3, 0.05f * i, 0.5f + 0.02f * i);
  RadianceShOptions o;
  o.samples = 64;
  o.seed = 7;
  std::vector<RadianceShEstimate<4>> a, b;
  tbb::task_arena(1).execute([&] { a = radiance_sh<4>(scene, p, o); });
  tbb::task_arena(2).execute([&] { b = radiance_sh<4>(scene, p, o); });
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(a[i].mean, b[i].mean);
    EXPECT_EQ(a[i].std_error, b[i].std_error);
    EXPECT_EQ(a[i].rays, b[i].rays);
  }
  o.seed = 8;
  const auto c = radiance_sh<4>(scene, p, o);
  EXPECT_NE(c[0].mean, a[0].mean);
}

TEST(RadianceSh, RejectsBadInput) {
  PENUMBRA_STABILITY("non-finite points, bad options; an empty scene",
                     "std::invalid_argument naming the point; empty scene black, finite", "-");
  SceneDesc d;
  const Scene scene(d);
  const std::vector<glm::vec3> p = {{0, 0, 0}, {0, std::nanf(""), 0}};
  EXPECT_THROW(
      {
        try {
          radiance_sh<3>(scene, p);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("points[1]"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  RadianceShOptions o;
  o.samples = 1;
  const std::vector<glm::vec3> q = {{0, 0, 0}};
  EXPECT_THROW(radiance_sh<3>(scene, q, o), std::invalid_argument);
  // Empty scene: black, finite.
  const auto e = radiance_sh<3>(scene, q);
  EXPECT_EQ(e[0].mean[0][0], 0.0f);
}

}  // namespace
}  // namespace penumbra::reference
