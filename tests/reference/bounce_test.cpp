#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/stability.h"
#include "penumbra/reference/estimators.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

using test::kPi;
using test::within_error;

BounceOptions bounce_opts(int samples = 256, int bounce_samples = 4) {
  BounceOptions o;
  o.samples = samples;
  o.bounce_samples = bounce_samples;
  o.seed = 11;
  return o;
}

RgbEstimate one_bounce(const Scene& s, const Receiver& r, const BounceOptions& o = bounce_opts()) {
  return indirect_irradiance(s, std::span(&r, 1), o)[0];
}

// Projected solid angle int_polygon max(0, n.w) dw of a planar polygon entirely in front of a
// point (vertices relative to the point, in order): Lambert's formula, half the sum over the
// edges of (edge angle) x (n . unit normal of the plane through the point and the edge).
double projected_solid_angle(const std::vector<glm::dvec3>& v, glm::dvec3 n) {
  double sum = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 a = glm::normalize(v[i]), b = glm::normalize(v[(i + 1) % v.size()]);
    const double gamma = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += gamma * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return std::abs(sum) / 2;
}

// Irradiance from a uniform sphere of radiance 1, angular radius sigma (sin^2 sigma given), at
// angle theta from the normal, clipped by the horizon: the closed form of Snyder 1996 ("Area
// light sources for real-time graphics", MSR-TR-96-11) as written in Lagarde and de Rousiers
// 2014 ("Moving Frostbite to PBR", listing 7). Checked against quadrature below.
double sphere_irradiance(double cos_theta, double sin2_sigma) {
  if (cos_theta * cos_theta > sin2_sigma) return kPi * sin2_sigma * std::max(0.0, cos_theta);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  const double x = std::sqrt(1 / sin2_sigma - 1);
  const double y = -x * cos_theta / sin_theta;
  const double s = sin_theta * std::sqrt(std::max(0.0, 1 - y * y));
  return std::max(0.0, (cos_theta * std::acos(y) - x * s) * sin2_sigma + std::atan(s / x));
}

// A flat square height field (one cell of side 2 half, 2 triangles) at z = 0.
HeightFieldInstance plane(float half, glm::vec3 albedo) {
  return {test::flat_field(2, 2, 2 * half, 0.0f), {-half, -half, 0}, albedo};
}

// A large Lambertian plane (albedo a) under a uniform sky L: every point of its upper side sees
// the whole sky, so its radiance is a L and a receiver at height h facing down gets
// E_ind = a L Phi, Phi the projected solid angle of the square (pi (1 - O((h / half)^2))).
// A receiver facing up gets exactly nothing from it.
TEST(IndirectIrradiance, LambertianPlaneUnderUniformSky) {
  const glm::vec3 L(1.0f, 1.0f, 1.0f), a(0.5f, 0.25f, 0.8f);
  const float half = 20, h = 1;
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(64, 32, L), 0};
  d.height_fields.push_back(plane(half, a));
  const Scene s(d);
  const Receiver down{{0, 0, h}, {0, 0, -1}};
  const RgbEstimate e = one_bounce(s, down, bounce_opts(1024));
  // Exact, from the ray origin (the receiver moved by the automatic offset along its normal).
  const double z = h - 1e-5 * s.extent();
  const double phi = projected_solid_angle(
      {{-half, -half, -z}, {half, -half, -z}, {half, half, -z}, {-half, half, -z}}, {0, 0, -1});
  EXPECT_NEAR(phi, kPi, 0.01);
  EXPECT_EQ(e.samples, 1024u);
  EXPECT_GE(e.dof, 30u);
  for (int c = 0; c < 3; ++c) {
    const double exact = a[c] * L[c] * phi;
    EXPECT_TRUE(within_error(e.mean[c], e.std_error[c], exact, 1e-5 * exact)) << c;
    EXPECT_LT(e.std_error[c], 0.01 * exact) << c;
  }
  // Rays: one per direction, plus up to bounce_samples shadow rays per hit.
  EXPECT_GT(e.rays, e.samples);
  EXPECT_LE(e.rays, e.samples * 5);

  const RgbEstimate up = one_bounce(s, {{0, 0, h}, {0, 0, 1}});
  EXPECT_EQ(up.mean, glm::vec3(0));
  EXPECT_EQ(up.std_error, glm::vec3(0));
  EXPECT_EQ(up.rays, up.samples);  // first-hit rays only, all escaping

  // The total is combine(direct, indirect): the sky's direct part is what the plane leaves
  // uncovered, L (pi - Phi).
  IrradianceOptions io;
  io.samples = 1024;
  const RgbEstimate direct = environment_irradiance(s, std::span(&down, 1), io)[0];
  const RgbEstimate total = combine(direct, e);
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(within_error(direct.mean[c], direct.std_error[c], L[c] * (kPi - phi), 1e-6)) << c;
    EXPECT_FLOAT_EQ(total.mean[c], direct.mean[c] + e.mean[c]);
  }
}

// Black albedo (the default) gives exactly zero and casts no ray; an occluder (black) between
// receiver and reflector removes the bounce.
TEST(IndirectIrradiance, BlackAlbedoAndBlockedReflectorGiveZero) {
  PENUMBRA_STABILITY("black albedo; an occluder between receiver and reflector; nothing emits",
                     "exactly zero, no rays wasted", "-");
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(16, 8, glm::vec3(1)), 0};
  d.lights = {{{0, 0, 5}, 1, {10, 10, 10}, "lamp"}};
  d.height_fields.push_back(plane(20, glm::vec3(0)));
  const Receiver r{{0, 0, 1}, {0, 0, -1}};
  {
    const Scene s(d);
    EXPECT_FALSE(s.reflects());
    const RgbEstimate e = one_bounce(s, r);
    EXPECT_EQ(e.mean, glm::vec3(0));
    EXPECT_EQ(e.std_error, glm::vec3(0));
    EXPECT_EQ(e.rays, 0u);
    EXPECT_EQ(e.samples, 256u);
  }
  d.height_fields[0].albedo = glm::vec3(0.7f);
  {
    const Scene s(d);
    EXPECT_TRUE(s.reflects());
    EXPECT_GT(one_bounce(s, r).mean.x, 1.0f);  // lit by sky and lamp: about 0.7 (pi + 0.13 pi 10)
  }
  // A black quad at z = 0.5, larger than the reflector: every first hit is on it.
  d.meshes.push_back({test::quad(40, 0.5f), glm::mat4(1.0f)});
  {
    const Scene s(d);
    const RgbEstimate e = one_bounce(s, r);
    EXPECT_EQ(e.mean, glm::vec3(0));
    EXPECT_EQ(e.std_error, glm::vec3(0));
    EXPECT_EQ(e.rays, e.samples);  // first-hit rays only: black hits cast no shadow rays
  }
  // Nothing emits: zero, no rays.
  d = {};
  d.height_fields.push_back(plane(20, glm::vec3(1)));
  const Scene dark(d);
  EXPECT_EQ(one_bounce(dark, r).mean, glm::vec3(0));
  EXPECT_EQ(one_bounce(dark, r).rays, 0u);
}

// A convex reflector alone under a uniform sky L: every point of it sees the whole hemisphere
// above its tangent plane, so its radiance is a L and a receiver seeing it as a cap of angular
// radius alpha at angle beta from its normal (cap above the horizon) gets
// E_ind = a L pi sin^2(alpha) cos(beta).
TEST(IndirectIrradiance, SphereReflectorUnderUniformSky) {
  const glm::vec3 a(0.9f, 0.5f, 0.1f);
  const float dist = 3, radius = 1.5f;  // alpha = 30 degrees
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(32, 16, glm::vec3(2)), 0};
  d.spheres = {{{0, 0, -dist}, radius, "ball", a}};
  const Scene s(d);
  const glm::vec3 n = glm::normalize(glm::vec3(0.4f, 0, -1));
  const RgbEstimate e = one_bounce(s, {{0, 0, 0}, n}, bounce_opts(1024));
  EXPECT_GE(e.dof, 30u);
  const double sin2 = (radius / dist) * (radius / dist), cos_b = -n.z;
  for (int c = 0; c < 3; ++c) {
    const double exact = a[c] * 2 * kPi * sin2 * cos_b;
    EXPECT_TRUE(within_error(e.mean[c], e.std_error[c], exact, 1e-5 * exact)) << c;
  }
}

// The light's closed form against quadrature, in the three regimes (above, straddling, below
// the horizon).
TEST(IndirectIrradiance, SphereLightClosedFormMatchesQuadrature) {
  for (double sigma : {0.1, 0.5, 1.0}) {
    for (double theta : {0.2, 1.2, 1.5, 1.7, 2.0, 2.8}) {
      const glm::dvec3 axis(std::sin(theta), 0, std::cos(theta));
      const double quad = test::cap_integral(axis, std::cos(sigma), 400, 800,
                                             [](glm::dvec3 w) { return std::max(0.0, w.z); });
      EXPECT_NEAR(sphere_irradiance(std::cos(theta), std::sin(sigma) * std::sin(sigma)), quad, 2e-5)
          << sigma << " " << theta;
    }
  }
}

// A sphere reflector (albedo a) lit by one spherical light, no sky: its radiance
// a / pi * E_light(x) has a terminator; the exact E_ind is a quadrature over the cap it subtends
// at the receiver (Gauss-Legendre x azimuths, test::cap_integral) of that radiance (the light's
// closed form above at each point) times the receiver's cosine.
TEST(IndirectIrradiance, SphereReflectorLitBySphereLightMatchesQuadrature) {
  const glm::vec3 a(0.8f, 0.5f, 0.2f), Le(20, 10, 5);
  const glm::dvec3 center(0, 0, -3), light(3.5, 0, -1.5);
  const double radius = 1.5, light_radius = 0.5;
  SceneDesc d;
  d.spheres = {{glm::vec3(center), float(radius), "ball", a}};
  d.lights = {{glm::vec3(light), float(light_radius), Le, "lamp"}};
  const Scene s(d);
  const glm::dvec3 p(0.0), n = glm::normalize(glm::dvec3(0.3, 0, -1));
  const glm::dvec3 to_c = center - p;
  const double dist = glm::length(to_c);
  // Irradiance per unit light radiance at the first hit along w.
  const auto bounce = [&](glm::dvec3 w) {
    const double b = glm::dot(to_c, w);
    const double t = b - std::sqrt(std::max(0.0, radius * radius - (dist * dist - b * b)));
    const glm::dvec3 x = p + t * w, nx = (x - center) / radius;
    const glm::dvec3 to_l = light - x;
    const double l2 = glm::dot(to_l, to_l);
    const double e =
        sphere_irradiance(glm::dot(nx, to_l) / std::sqrt(l2), light_radius * light_radius / l2);
    return e / kPi * std::max(0.0, glm::dot(n, w));
  };
  const double cos_alpha = std::sqrt(1 - radius * radius / (dist * dist));
  const double fine = test::cap_integral(to_c / dist, cos_alpha, 600, 1200, bounce);
  const double coarse = test::cap_integral(to_c / dist, cos_alpha, 300, 600, bounce);
  const double quad_err = std::abs(fine - coarse);  // bounds the fine one's error (O(h^2))
  EXPECT_LT(quad_err, 1e-4 * fine);
  const RgbEstimate e = one_bounce(s, {glm::vec3(p), glm::vec3(n)}, bounce_opts(4096));
  EXPECT_GE(e.dof, 30u);
  for (int c = 0; c < 3; ++c) {
    const double exact = a[c] * Le[c] * fine;
    EXPECT_TRUE(
        within_error(e.mean[c], e.std_error[c], exact, a[c] * Le[c] * quad_err + 1e-5 * exact))
        << c;
    EXPECT_LT(e.std_error[c], 0.03 * exact) << c;
  }
  // More samples per hit (16): the same mean. (Its error bar is hardly smaller: the variance
  // across first-hit directions -- the terminator, the sphere's outline -- dominates.)
  const RgbEstimate more = one_bounce(s, {glm::vec3(p), glm::vec3(n)}, bounce_opts(4096, 16));
  EXPECT_TRUE(within_error(more.mean.x, more.std_error.x, a.x * Le.x * fine,
                           a.x * Le.x * quad_err + 1e-5 * fine));
}

// The error bars are calibrated: 100 independent estimates (one stream per receiver) of the
// sphere-light case at 4096 samples, z = (estimate - exact) / std_error: mean z^2 near 1 (the
// exact value by the quadrature above).
TEST(IndirectIrradiance, ErrorBarsAreCalibrated) {
  SceneDesc d;
  d.spheres = {{{0, 0, -3}, 1.5f, "ball", {1, 1, 1}}};
  d.lights = {{{3.5f, 0, -1.5f}, 0.5f, {1, 1, 1}, "lamp"}};
  const Scene s(d);
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 0, -1));
  const double exact = 0.00332206009;  // SphereReflectorLitBySphereLightMatchesQuadrature
  const std::vector<Receiver> rs(100, Receiver{{0, 0, 0}, glm::vec3(n)});
  const auto e = indirect_irradiance(s, rs, bounce_opts(4096));
  double z2 = 0;
  int beyond3 = 0;
  for (const RgbEstimate& r : e) {
    ASSERT_GE(r.dof, 30u);
    const double z = (r.mean.x - exact) / r.std_error.x;
    EXPECT_LT(std::abs(z), 6);
    beyond3 += std::abs(z) > 3;
    z2 += z * z;
  }
  EXPECT_GT(z2 / rs.size(), 0.6);
  EXPECT_LT(z2 / rs.size(), 1.5);
  EXPECT_LE(beyond3, 4);
}

// Same seed: bit-identical on 1 and 2 threads; another seed differs.
TEST(IndirectIrradiance, DeterministicAcrossThreadCounts) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::cosine_sky_map(32, 16), 0.3f};
  d.lights = {{{2, 1, 4}, 0.5f, {5, 4, 3}, ""}};
  d.spheres = {{{1, 1, 1}, 0.7f, "", {0.6f, 0.6f, 0.6f}}, {{-1, 0, 0.5f}, 0.4f, "", {}}};
  d.height_fields.push_back(plane(10, glm::vec3(0.3f, 0.4f, 0.5f)));
  const Scene s(d);
  std::vector<Receiver> rs;
  for (int i = 0; i < 200; ++i) {
    rs.push_back({{0.02f * i - 2, 0.01f * i - 1, 0.0f}, {std::sin(0.1f * i), 0.0f, 1.0f}});
  }
  const BounceOptions o = bounce_opts(64);
  std::vector<RgbEstimate> one_thread, two_threads;
  tbb::task_arena(1).execute([&] { one_thread = indirect_irradiance(s, rs, o); });
  tbb::task_arena(2).execute([&] { two_threads = indirect_irradiance(s, rs, o); });
  ASSERT_EQ(one_thread.size(), two_threads.size());
  EXPECT_EQ(
      std::memcmp(one_thread.data(), two_threads.data(), one_thread.size() * sizeof(RgbEstimate)),
      0);
  BounceOptions other = o;
  other.seed = o.seed + 1;
  const auto three = indirect_irradiance(s, rs, other);
  int differ = 0;
  for (std::size_t i = 0; i < rs.size(); ++i) differ += three[i].mean != one_thread[i].mean;
  EXPECT_GT(differ, 150);
}

TEST(IndirectIrradiance, BadInputThrows) {
  PENUMBRA_STABILITY("non-finite receivers, bad sample counts",
                     "std::invalid_argument naming the receiver", "-");
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(8, 4, glm::vec3(1)), 0};
  d.height_fields.push_back(plane(5, glm::vec3(0.5f)));
  const Scene s(d);
  std::vector<Receiver> rs(3, Receiver{{0, 0, 1}, {0, 0, -1}});
  rs[1].normal = {0, 0, 0};
  try {
    indirect_irradiance(s, rs);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("receivers[1]"), std::string::npos) << e.what();
  }
  rs[1] = rs[0];
  BounceOptions o;
  o.samples = 0;
  EXPECT_THROW(indirect_irradiance(s, rs, o), std::invalid_argument);
  o = {};
  o.bounce_samples = 0;
  EXPECT_THROW(indirect_irradiance(s, rs, o), std::invalid_argument);
  o = {};
  o.ray_offset = -1;
  EXPECT_THROW(indirect_irradiance(s, rs, o), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
