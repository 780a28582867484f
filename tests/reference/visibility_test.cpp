#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "penumbra/reference/estimators.h"
#include "penumbra/sh/basis.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

using test::kPi;
using test::within_error;

double legendre(int l, double x) {
  if (l == 0) return 1;
  double p0 = 1, p1 = x;
  for (int k = 2; k <= l; ++k) {
    const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return p1;
}

// SH coefficients of the indicator of the cap {w : a.w >= cos_a}: zonal about a with
// z_l = 2 pi N_l int_{cos_a}^1 P_l, int_x^1 P_l = (P_{l-1}(x) - P_{l+1}(x)) / (2l + 1) (l >= 1),
// rotated to a: f_lm = sqrt(4 pi / (2l+1)) z_l y_lm(a) = 2 pi (int P_l) y_lm(a).
template <int N>
std::array<double, N * N> cap_sh(glm::vec3 a, double cos_a) {
  const sh::Coeffs<N> y = sh::eval_basis<N>(glm::normalize(a));
  std::array<double, N * N> out{};
  for (int l = 0; l < N; ++l) {
    const double integral =
        l == 0 ? 1 - cos_a : (legendre(l - 1, cos_a) - legendre(l + 1, cos_a)) / (2 * l + 1);
    for (int m = -l; m <= l; ++m) out[sh::index(l, m)] = 2 * kPi * integral * y[sh::index(l, m)];
  }
  return out;
}

// Every coefficient within 5 sigma (many correlated comparisons: see within_error), with error
// bars of at least `min_dof` degrees of freedom (Student-t, 12 dof: P(|t| > 5) = 3e-4).
template <int N>
void expect_matches(const ShEstimate<N>& e, const std::array<double, N * N>& exact,
                    const char* what, unsigned min_dof = 12) {
  EXPECT_GE(e.dof, min_dof) << what;
  for (int i = 0; i < N * N; ++i) {
    EXPECT_TRUE(within_error(e.mean[i], e.std_error[i], exact[i], 2e-5, 5)) << what << " i=" << i;
  }
}

struct Blocker {
  glm::vec3 center;
  float radius;
};

template <int N>
void check_sphere_cap(VisibilityDomain domain, glm::vec3 normal, const std::vector<Blocker>& cases,
                      int samples) {
  for (const Blocker& b : cases) {
    SceneDesc d;
    d.spheres = {{b.center, b.radius, "blocker"}};
    const Scene s(d);
    VisibilityOptions o;
    o.samples = samples;
    o.seed = 3;
    o.domain = domain;
    const Receiver r{{0, 0, 0}, normal};
    const ShEstimate<N> e = visibility_sh<N>(s, std::span(&r, 1), o)[0];
    const double dist = glm::length(b.center),
                 cos_a = std::sqrt(1 - b.radius * b.radius / (dist * dist));
    std::array<double, N* N> exact = cap_sh<N>(b.center, cos_a);
    if (domain == VisibilityDomain::kSphere) {
      for (double& v : exact) v = -v;
      exact[0] += std::sqrt(4 * kPi);
    } else {  // hemisphere (cap above the horizon): the hemisphere's cap minus the sphere's
      const auto hemi = cap_sh<N>(normal, 0.0);
      for (int i = 0; i < N * N; ++i) exact[i] = hemi[i] - exact[i];
    }
    expect_matches<N>(e, exact, domain == VisibilityDomain::kSphere ? "sphere" : "hemisphere");
  }
}

TEST(VisibilitySh, SingleSphereMatchesAnalyticCapWholeSphere) {
  const std::vector<Blocker> cases = {{{0, 0, 3}, 1}, {{2, -1, 0.5f}, 1.5f}, {{-4, 3, -2}, 1.2f}};
  // V_0's dof is about a third of the strata the outline crosses: 65536 samples give the
  // smallest cap (12.9 degrees) dof ~22.
  check_sphere_cap<4>(VisibilityDomain::kSphere, {0, 0, 0}, cases, 65536);  // free-space point
  check_sphere_cap<6>(VisibilityDomain::kSphere, {0, 0, 0}, cases, 65536);
  check_sphere_cap<2>(VisibilityDomain::kSphere, {0, 0, 0}, cases, 65536);
}

TEST(VisibilitySh, SingleSphereMatchesAnalyticCapHemisphere) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  check_sphere_cap<4>(VisibilityDomain::kHemisphere, n, {{{0, 0, 3}, 1}, {{1, 1, 2}, 0.7f}}, 32768);
  check_sphere_cap<5>(VisibilityDomain::kHemisphere, n, {{{0.5f, -1, 2}, 0.9f}}, 32768);
}

// Cosine domain: T_i = int V max(0, n.w) y_i; the exact value by quadrature over the
// hemisphere and the (above-horizon) cap. And sqrt(4 pi) T_0 is the irradiance under a unit
// constant sky, pi (1 - sin^2 a cos b).
TEST(VisibilitySh, CosineTransferMatchesQuadratureAndIrradiance) {
  const glm::vec3 n = glm::normalize(glm::vec3(-0.3f, 0.2f, 1.0f));
  const glm::vec3 c(0.5f, 1.0f, 3.0f);
  const float radius = 1.2f;
  SceneDesc d;
  d.spheres = {{c, radius, ""}};
  const Scene s(d);
  VisibilityOptions o;
  o.samples = 16384;
  o.domain = VisibilityDomain::kCosine;
  const Receiver r{{0, 0, 0}, n};
  const ShEstimate<4> e = visibility_sh<4>(s, std::span(&r, 1), o)[0];
  const double cos_a = std::sqrt(1 - radius * radius / glm::dot(c, c));
  for (int i = 0; i < 16; ++i) {
    auto f = [&](const glm::dvec3& w) {
      return std::max(0.0, glm::dot(w, glm::dvec3(n))) * sh::eval_basis<4>(glm::vec3(w))[i];
    };
    const double exact = test::cap_integral(glm::dvec3(n), 0.0, 24, 48, f) -
                         test::cap_integral(glm::dvec3(c), cos_a, 24, 48, f);
    EXPECT_TRUE(within_error(e.mean[i], e.std_error[i], exact, 1e-5, 5)) << i;
  }
  EXPECT_GE(e.dof, 15u);
  const double sin2 = radius * radius / glm::dot(c, c);
  const double irradiance = kPi * (1 - sin2 * glm::dot(n, glm::normalize(c)));
  EXPECT_TRUE(within_error(std::sqrt(4 * kPi) * e.mean[0], std::sqrt(4 * kPi) * e.std_error[0],
                           irradiance, 1e-5));
}

// Unoccluded: V_0 = sqrt(4 pi) exactly (zero variance), the rest zero within error. On a flat
// field with the whole sphere, the lower hemisphere is blocked: V = hemisphere indicator.
TEST(VisibilitySh, UnoccludedAndGroundPlane) {
  const Scene empty{SceneDesc{}};
  const Receiver r{{1, 2, 3}, {0, 0, 0}};
  const ShEstimate<4> e = visibility_sh<4>(empty, std::span(&r, 1))[0];
  EXPECT_NEAR(e.mean[0], std::sqrt(4 * kPi), 1e-5);
  EXPECT_EQ(e.std_error[0], 0.0f);
  for (int i = 1; i < 16; ++i) EXPECT_TRUE(within_error(e.mean[i], e.std_error[i], 0, 1e-6, 5));

  SceneDesc d;
  const HeightFieldInstance field{test::flat_field(64, 64, 0.5f, 1.0f), {-16, -16, 0}};
  d.height_fields.push_back(field);
  const Scene ground(d);
  const std::vector<Receiver> all = height_field_receivers(field);
  std::vector<Receiver> rs;  // receivers away from the border (downward rays must land)
  for (int y = 24; y < 40; y += 5) {
    for (int x = 24; x < 40; x += 5) rs.push_back(all[y * 64 + x]);
  }
  const auto v = visibility_sh<3>(ground, rs);
  const auto hemi = cap_sh<3>({0, 0, 1}, 0.0);
  // (The horizon falls on a stratum edge, so V_0 is nearly exact and its dof near 0.)
  for (const auto& g : v) expect_matches<3>(g, hemi, "ground", 0);
}

TEST(VisibilitySh, DeterministicAcrossThreadCountsAndChecksInput) {
  SceneDesc d;
  d.spheres = {{{0, 0, 2}, 1, ""}, {{1, 1, 1}, 0.5f, ""}};
  const Scene s(d);
  std::vector<Receiver> rs;
  for (int i = 0; i < 100; ++i) rs.push_back({{0.01f * i, 0, -0.5f}, {0, 0, 1}});
  VisibilityOptions o;
  o.samples = 128;
  o.domain = VisibilityDomain::kHemisphere;
  std::vector<ShEstimate<4>> a, b;
  tbb::task_arena(1).execute([&] { a = visibility_sh<4>(s, rs, o); });
  tbb::task_arena(2).execute([&] { b = visibility_sh<4>(s, rs, o); });
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(ShEstimate<4>)), 0);
  EXPECT_EQ(a[0].samples, 128u);
  rs[5].normal = {0, 0, 0};
  EXPECT_THROW(visibility_sh<4>(s, rs, o), std::invalid_argument);  // hemisphere needs a normal
  o.domain = VisibilityDomain::kSphere;
  EXPECT_NO_THROW(visibility_sh<4>(s, rs, o));
}

}  // namespace
}  // namespace penumbra::reference
