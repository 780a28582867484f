#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/stability.h"
#include "penumbra/reference/estimators.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

using test::kPi;
using test::within_error;

Scene sky_scene(data::EnvironmentMap map, float rot = 0) {
  SceneDesc d;
  d.environment = EnvironmentLight{std::move(map), rot};
  return Scene(d);
}

using test::unit;

IrradianceOptions with(EnvironmentStrategy s, MisHeuristic h = MisHeuristic::kPower,
                       int samples = 256) {
  IrradianceOptions o;
  o.strategy = s;
  o.heuristic = h;
  o.samples = samples;
  o.seed = 42;
  return o;
}

TEST(EnvironmentIrradiance, ConstantSkyGivesPiL) {
  const glm::vec3 L(1.0f, 0.5f, 2.0f);
  const Scene s = sky_scene(test::constant_map(64, 32, L));
  std::vector<Receiver> rs;
  for (int i = 0; i < 8; ++i) rs.push_back({{0, 0, 0}, unit(0.4f * i, 1.3f * i)});
  for (auto [strategy, h] : {std::pair{EnvironmentStrategy::kMis, MisHeuristic::kPower},
                             std::pair{EnvironmentStrategy::kMis, MisHeuristic::kBalance},
                             std::pair{EnvironmentStrategy::kCosine, MisHeuristic::kPower},
                             std::pair{EnvironmentStrategy::kEnvironment, MisHeuristic::kPower}}) {
    const auto e = environment_irradiance(s, rs, with(strategy, h));
    for (const RgbEstimate& r : e) {
      EXPECT_EQ(r.samples, 256u);
      for (int c = 0; c < 3; ++c) {
        // 5 sigma: 96 comparisons (see within_error).
        EXPECT_TRUE(within_error(r.mean[c], r.std_error[c], kPi * L[c], 1e-5 * kPi * L[c], 5))
            << "strategy " << int(strategy) << " channel " << c;
      }
      // The environment-only estimate of a constant sky has a relative error near 1/sqrt(n).
      if (strategy == EnvironmentStrategy::kEnvironment) {
        EXPECT_LT(r.std_error.x, 0.03f * kPi);
      }
    }
  }
}

// Cosine sky L(w) = max(0, w_z): the estimate matches the exact integral of the
// piecewise-constant map, and that matches the closed form (2/3)(sin g + (pi - g) cos g).
TEST(EnvironmentIrradiance, CosineSkyMatchesClosedForm) {
  const auto map = test::cosine_sky_map(256, 128);
  const Scene s = sky_scene(map, 0.4f);
  for (double g_deg : {0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0}) {
    const float g = static_cast<float>(g_deg * kPi / 180);
    const Receiver r{{0, 0, 0}, unit(g, 0.3f)};
    const double exact = test::exact_map_irradiance(map, 0.4f, r.normal).x;
    // Texel averaging discretises the sky: about 1e-4 relative at 256 x 128.
    EXPECT_NEAR(exact, test::cosine_sky_irradiance(g), 5e-4) << g_deg;
    IrradianceOptions o = with(EnvironmentStrategy::kMis);
    o.samples = 1024;
    const RgbEstimate e = environment_irradiance(s, std::span(&r, 1), o)[0];
    EXPECT_TRUE(within_error(e.mean.x, e.std_error.x, exact, 1e-6)) << g_deg;
    EXPECT_LT(e.std_error.x, 0.01 * 2 * kPi / 3) << g_deg;
  }
}

// A map lit only around +x (L = max(0, x) per texel centre), rotated by 0.9 rad: checks the
// rotation convention end to end against the exact sum over texels.
TEST(EnvironmentIrradiance, RotatedMapMatchesExactTexelSum) {
  const auto map = test::make_map(128, 64, [](int x, int y) {
    const double phi = 2 * kPi * (x + 0.5) / 128, theta = kPi * (y + 0.5) / 64;
    return glm::vec3(static_cast<float>(std::max(0.0, std::sin(theta) * std::cos(phi))), 0.2f,
                     0.0f);
  });
  const Scene s = sky_scene(map, 0.9f);
  for (int i = 0; i < 6; ++i) {
    const Receiver r{{0, 0, 0}, unit(0.5f * i + 0.2f, 1.1f * i)};
    const glm::dvec3 exact = test::exact_map_irradiance(map, 0.9f, r.normal);
    const RgbEstimate e =
        environment_irradiance(s, std::span(&r, 1), with(EnvironmentStrategy::kMis))[0];
    for (int c = 0; c < 2; ++c) {
      EXPECT_TRUE(within_error(e.mean[c], e.std_error[c], exact[c], 1e-6)) << i << " " << c;
    }
    EXPECT_EQ(e.mean.z, 0.0f);
  }
}

// One occluding sphere of angular radius a at angle b from n, cap fully above the horizon,
// under a constant sky: E = pi L (1 - sin^2 a cos b) (a uniform cap's vector irradiance is
// pi L sin^2 a along its axis). Over 100 independent estimates with dof >= 15 the error bars are
// calibrated: mean z^2 near 1 (1.07 for Student-t with 30 dof, sd 0.16), thin tails. (A binary
// integrand's dof is about a third of the strata its outline crosses: 8192 samples give
// cosine-only sampling ~30.)
TEST(EnvironmentIrradiance, SphereBlockerUnderConstantSkyIsCalibrated) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(64, 32, glm::vec3(1)), 0};
  const float a = 0.5f, b = 0.6f, dist = 5;
  d.spheres = {{dist * unit(b, 2.0f), dist * std::sin(a), "blocker"}};
  const Scene s(d);
  const double exact = kPi * (1 - std::sin(a) * std::sin(a) * std::cos(b));
  const std::vector<Receiver> rs(100, Receiver{{0, 0, 0}, {0, 0, 1}});
  for (auto strategy : {EnvironmentStrategy::kMis, EnvironmentStrategy::kCosine}) {
    const auto e = environment_irradiance(s, rs, with(strategy, MisHeuristic::kPower, 8192));
    double z2 = 0;
    int beyond3 = 0;
    for (const RgbEstimate& r : e) {
      ASSERT_GE(r.dof, 15u);
      const double z = (r.mean.x - exact) / r.std_error.x;
      EXPECT_LT(std::abs(z), 6);
      beyond3 += std::abs(z) > 3;
      z2 += z * z;
    }
    EXPECT_GT(z2 / rs.size(), 0.6) << int(strategy);
    EXPECT_LT(z2 / rs.size(), 1.5) << int(strategy);
    EXPECT_LE(beyond3, 4) << int(strategy);  // expected ~0.3 (normal) to ~0.7 (t, 20 dof)
  }
}

// Below a large flat blocker nothing of a sky above the horizon arrives, whatever the normal;
// facing straight down under a constant sky, the blocker is not in the hemisphere at all.
TEST(EnvironmentIrradiance, HalfSpaceBlockerGivesZeroFromBelow) {
  PENUMBRA_STABILITY("a receiver below a large flat blocker", "exactly zero, whatever the normal",
                     "-");
  // (The sky stops 22.5 degrees above the horizon, so the thin gap under the blocker's far
  // edge, 1e-4 rad, sees nothing.)
  SceneDesc d;
  d.environment = EnvironmentLight{
      test::make_map(64, 32, [](int, int y) { return glm::vec3(y < 12 ? 1.0f : 0.0f); }), 0};
  d.meshes.push_back({test::quad(1e4f, 1.0f), glm::mat4(1.0f)});
  const Scene s(d);
  std::vector<Receiver> rs;
  for (int i = 0; i < 6; ++i) rs.push_back({{3, -2, 0}, unit(0.5f * i, 0.7f * i)});
  for (const RgbEstimate& e : environment_irradiance(s, rs, with(EnvironmentStrategy::kMis))) {
    EXPECT_EQ(e.mean, glm::vec3(0));
    EXPECT_EQ(e.std_error, glm::vec3(0));
  }
  SceneDesc c = d;
  c.environment = EnvironmentLight{test::constant_map(64, 32, glm::vec3(2)), 0};
  const Scene s2(c);
  const Receiver down{{0, 0, 0}, {0, 0, -1}};
  const RgbEstimate e =
      environment_irradiance(s2, std::span(&down, 1), with(EnvironmentStrategy::kCosine))[0];
  EXPECT_NEAR(e.mean.x, 2 * kPi, 1e-5);
}

// Receivers on a large flat height field (normal +z, automatic offset) under a constant sky:
// cosine sampling has zero variance, so any self-intersection would show as a deficit.
TEST(EnvironmentIrradiance, NoSelfShadowingOnAFlatField) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(32, 16, glm::vec3(1)), 0};
  const HeightFieldInstance field{test::flat_field(256, 256, 1.0f, 7.0f), {-128, -128, 0}};
  d.height_fields.push_back(field);
  const Scene s(d);
  std::vector<Receiver> rs = height_field_receivers(field);
  rs.resize(2000);
  for (const RgbEstimate& e : environment_irradiance(
           s, rs, with(EnvironmentStrategy::kCosine, MisHeuristic::kPower, 64))) {
    EXPECT_NEAR(e.mean.x, kPi, 1e-5 * kPi);
  }
}

TEST(EnvironmentIrradiance, InsideAnOccluderSphereIsZero) {
  PENUMBRA_STABILITY("a receiver inside an occluding sphere", "exactly zero", "-");
  SceneDesc d;
  d.environment = EnvironmentLight{test::constant_map(32, 16, glm::vec3(1)), 0};
  d.spheres = {{{0, 0, 0}, 2, "shell"}};
  const Scene s(d);
  const Receiver r{{0.5f, 0.2f, -0.3f}, {1, 1, 0}};
  const RgbEstimate e = environment_irradiance(s, std::span(&r, 1))[0];
  EXPECT_EQ(e.mean, glm::vec3(0));
  EXPECT_EQ(e.std_error, glm::vec3(0));
}

TEST(EnvironmentIrradiance, AlbedoGivesOutgoingRadiance) {
  const Scene s = sky_scene(test::cosine_sky_map(64, 32));
  const Receiver r{{0, 0, 0}, unit(0.7f, 0.1f)};
  IrradianceOptions o = with(EnvironmentStrategy::kMis);
  const RgbEstimate e = environment_irradiance(s, std::span(&r, 1), o)[0];
  o.albedo = glm::vec3(0.5f, 0.25f, 1.0f);
  const RgbEstimate lo = environment_irradiance(s, std::span(&r, 1), o)[0];
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(lo.mean[c], e.mean[c] * (*o.albedo)[c] / std::numbers::pi_v<float>);
    EXPECT_FLOAT_EQ(lo.std_error[c], e.std_error[c] * (*o.albedo)[c] / std::numbers::pi_v<float>);
  }
}

// Same seed: bit-identical results on 1 and 2 threads; another seed: different results.
TEST(EnvironmentIrradiance, DeterministicAcrossThreadCounts) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::cosine_sky_map(64, 32), 0.3f};
  d.spheres = {{{1, 1, 2}, 1, ""}, {{-2, 0, 1}, 0.5f, ""}};
  const Scene s(d);
  std::vector<Receiver> rs;
  for (int i = 0; i < 300; ++i) rs.push_back({{0.01f * i, 0, 0}, unit(0.003f * i, 0.1f * i)});
  const IrradianceOptions o = with(EnvironmentStrategy::kMis, MisHeuristic::kPower, 64);
  std::vector<RgbEstimate> one, two;
  tbb::task_arena(1).execute([&] { one = environment_irradiance(s, rs, o); });
  tbb::task_arena(2).execute([&] { two = environment_irradiance(s, rs, o); });
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(RgbEstimate)), 0);
  IrradianceOptions other = o;
  other.seed = 43;
  const auto three = environment_irradiance(s, rs, other);
  int differ = 0;
  for (std::size_t i = 0; i < rs.size(); ++i) differ += three[i].mean != one[i].mean;
  EXPECT_GT(differ, 250);
}

// Independent samples: 16x the samples gives 1/4 the standard error. Stratified: at least that.
TEST(EnvironmentIrradiance, StandardErrorShrinksAsOneOverSqrtSamples) {
  SceneDesc d;
  d.environment = EnvironmentLight{test::cosine_sky_map(64, 32), 0};
  d.spheres = {{{0, 1, 3}, 1.5f, ""}};
  const Scene s(d);
  const std::vector<Receiver> rs(200, Receiver{{0, 0, 0}, unit(0.3f, 0.2f)});
  for (bool stratified : {false, true}) {
    double se[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      IrradianceOptions o = with(EnvironmentStrategy::kMis, MisHeuristic::kPower, k ? 1024 : 64);
      o.stratified = stratified;
      for (const RgbEstimate& e : environment_irradiance(s, rs, o)) se[k] += e.std_error.x;
    }
    const double ratio = se[0] / se[1];
    if (stratified) {
      EXPECT_GT(ratio, 3.6);
    } else {
      EXPECT_GT(ratio, 3.6);
      EXPECT_LT(ratio, 4.4);
    }
  }
}

// A sun-like map (sky plus a 5 degree disc 300x brighter, giving most of the irradiance): at
// 4096 samples (enough for cosine sampling to hit the sun ~30 times) MIS and cosine-only
// sampling agree within their errors and with the exact value, and MIS is far more precise.
TEST(EnvironmentIrradiance, MisBeatsCosineSamplingOnAPeakedMap) {
  const glm::vec3 sun = unit(0.8f, 0.5f);
  const auto map = test::make_map(256, 128, [&](int x, int y) {
    const glm::vec3 w = unit(static_cast<float>(kPi * (y + 0.5) / 128),
                             static_cast<float>(2 * kPi * (x + 0.5) / 256));
    const float sky = 0.3f + 0.7f * std::max(0.0f, w.z);
    return glm::dot(w, sun) > std::cos(0.087f) ? glm::vec3(300, 280, 250)
                                               : glm::vec3(0.6f, 0.8f, 1.0f) * sky;
  });
  const Scene s = sky_scene(map);
  const Receiver r{{0, 0, 0}, unit(0.3f, 2.0f)};
  const glm::dvec3 exact = test::exact_map_irradiance(map, 0, r.normal);
  const auto opts = [](EnvironmentStrategy st) { return with(st, MisHeuristic::kPower, 4096); };
  const RgbEstimate mis =
      environment_irradiance(s, std::span(&r, 1), opts(EnvironmentStrategy::kMis))[0];
  const RgbEstimate cos =
      environment_irradiance(s, std::span(&r, 1), opts(EnvironmentStrategy::kCosine))[0];
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(within_error(mis.mean[c], mis.std_error[c], exact[c], 1e-5 * exact[c]));
    EXPECT_TRUE(within_error(cos.mean[c], cos.std_error[c], exact[c], 1e-5 * exact[c]));
    const double joint = std::hypot(mis.std_error[c], cos.std_error[c]);
    EXPECT_LT(std::abs(mis.mean[c] - cos.mean[c]), 4 * joint);
    EXPECT_LT(mis.std_error[c], 0.1 * cos.std_error[c]);
    EXPECT_LT(mis.std_error[c], 0.005 * exact[c]);
  }
}

TEST(EnvironmentIrradiance, NoEnvironmentGivesZeroAndBadInputThrows) {
  PENUMBRA_STABILITY("no environment; non-finite receivers; bad options",
                     "zero; std::invalid_argument naming the receiver", "-");
  const Scene empty{SceneDesc{}};
  const Receiver r{{0, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(environment_irradiance(empty, std::span(&r, 1))[0].mean, glm::vec3(0));
  const Scene s = sky_scene(test::constant_map(8, 4, glm::vec3(1)));
  std::vector<Receiver> bad(3, r);
  bad[2].normal = {0, 0, 0};
  try {
    environment_irradiance(s, bad);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("receivers[2]"), std::string::npos) << e.what();
  }
  bad[2] = {{0, std::numeric_limits<float>::quiet_NaN(), 0}, {0, 0, 1}};
  EXPECT_THROW(environment_irradiance(s, bad), std::invalid_argument);
  IrradianceOptions o;
  o.samples = 0;
  EXPECT_THROW(environment_irradiance(s, std::span(&r, 1), o), std::invalid_argument);
  o = {};
  o.albedo = glm::vec3(-1);
  EXPECT_THROW(environment_irradiance(s, std::span(&r, 1), o), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
