// Accuracy of the blocker accumulation against the reference integrator (engine/reference): the
// irradiance at receivers on a ground plane (normal +z) under sphere blockers, lit by an
// environment map. Errors are relative to the mean unoccluded reference irradiance of the
// scene, so a value is "percent of the open-sky light". Measured values are printed; bounds sit
// above them with margin for the reference's noise (4,096 samples per receiver).
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "common/stability.h"
#include "penumbra/assets/exr.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/environment/environment_light_update.h"
#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

constexpr int N = 4;

using test::uniform_sky;

data::EnvironmentMap sky_map() {
  return assets::load_environment_map(std::filesystem::path(PENUMBRA_SHARED_DATA) / "hdri" /
                                      "sky.exr");
}

struct Errors {
  float rms = 0, max = 0;  // relative to the mean open-sky reference irradiance
  float shadow = 0;        // deepest reference shadow, relative to the same
};

// Receivers on z = 0 along x in [-4, 4] (33 points) and y = 0.5 beside.
std::vector<reference::Receiver> ground_receivers() {
  std::vector<reference::Receiver> out;
  for (int i = 0; i <= 32; ++i) {
    out.push_back({{-4.0f + 0.25f * i, 0.0f, 0.0f}, {0, 0, 1}});
    out.push_back({{-4.0f + 0.25f * i, 0.5f, 0.0f}, {0, 0, 1}});
  }
  return out;
}

template <int B = N>
Errors measure(const data::EnvironmentMap& map, const std::vector<WorldSphere>& spheres,
               const BlockerSettings& settings) {
  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{map, 0.0f};
  for (const WorldSphere& s : spheres) desc.spheres.push_back({s.centre, s.radius, ""});
  const reference::Scene with(desc);
  desc.spheres.clear();
  const reference::Scene open(desc);
  const std::vector<reference::Receiver> receivers = ground_receivers();
  reference::IrradianceOptions o;
  o.samples = 4096;
  const auto ref = reference::environment_irradiance(with, receivers, o);
  const auto ref_open = reference::environment_irradiance(open, receivers, o);

  BlockerAccumulation<B> acc(settings);
  acc.set_blockers(spheres);
  const sh::CoeffsRgb<B> radiance = sh::project_equirect<B>(map.rgb.data(), map.width, map.height);
  double open_mean = 0;
  for (const auto& r : ref_open) open_mean += r.mean.y / ref_open.size();
  Errors e;
  double sq = 0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 ours = acc.irradiance(radiance, receivers[i].position, receivers[i].normal);
    EXPECT_TRUE(std::isfinite(ours.y));
    const double d = (ours.y - ref[i].mean.y) / open_mean;
    sq += d * d;
    e.max = std::max(e.max, static_cast<float>(std::abs(d)));
    e.shadow = std::max(e.shadow, static_cast<float>(1 - ref[i].mean.y / open_mean));
  }
  e.rms = static_cast<float>(std::sqrt(sq / receivers.size()));
  return e;
}

void print(const char* what, const Errors& e) {
  std::printf("%-44s rel RMS %6.2f%%  max %6.2f%%  (deepest reference shadow %5.1f%%)\n", what,
              100 * e.rms, 100 * e.max, 100 * e.shadow);
}

TEST(BlockerAccuracy, NoBlockersIsTheSkyAlone) {
  const Errors e = measure(uniform_sky(), {}, {});
  print("uniform sky, no blocker", e);
  EXPECT_LT(e.max, 0.01f);  // only the reference's noise
}

TEST(BlockerAccuracy, OneSphereOverAPlane) {
  const std::vector<WorldSphere> one = {{{0, 0, 2}, 1}};
  BlockerSettings product, log_brdf;
  log_brdf.shading = BlockerShading::kLogBrdf;
  const Errors a = measure(uniform_sky(), one, product);
  const Errors b = measure(uniform_sky(), one, log_brdf);
  const Errors c = measure(sky_map(), one, product);
  const Errors open = measure(sky_map(), {}, product);
  print("one sphere, uniform sky, product [Ren06]", a);
  print("one sphere, uniform sky, log-BRDF [Giraud]", b);
  print("sky.exr, no blocker", open);
  print("one sphere, sky.exr, product", c);
  EXPECT_GT(a.shadow, 0.2f);  // the scene does shadow
  EXPECT_LT(a.rms, 0.03f);    // measured 1.5%
  EXPECT_LT(a.max, 0.05f);    // 2.4%
  EXPECT_LT(b.rms, 0.03f);    // 1.7%
  EXPECT_LT(open.rms, 0.03f);
  // sky.exr's sun, eclipsed by the sphere for some receivers, is far above 4 bands: the hard
  // sun shadow is what 16 coefficients cannot hold (measured 19.7% RMS, 43% max).
  EXPECT_LT(c.rms, 0.25f);
}

// The map's sun as a key light ([Ambrosj16] ch. 4; key_light_visibility): the same scene with
// sky.exr's sun found by systems/environment, shaded as irradiance x cos x the share of its disc
// the sphere leaves, the rest of the map (its OEM without the sun) in SH. Against the reference:
// the hard shadow the SH alone cannot hold (19.7% RMS above) comes back.
TEST(BlockerAccuracy, OneSphereOverAPlaneWithTheSunAsKeyLight) {
  const std::vector<WorldSphere> one = {{{0, 0, 2}, 1}};
  components::EnvironmentLight env;
  env.map = std::make_shared<const data::EnvironmentMap>(sky_map());
  environment::update_environment_light(env, {});
  ASSERT_GE(env.sources.size(), 1u);
  const components::EnvironmentSource& sun = env.sources[0];

  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{*env.map, 0.0f};
  desc.spheres.push_back({one[0].centre, one[0].radius, ""});
  const reference::Scene with(desc);
  const std::vector<reference::Receiver> receivers = ground_receivers();
  reference::IrradianceOptions o;
  o.samples = 4096;
  const auto ref = reference::environment_irradiance(with, receivers, o);
  desc.spheres.clear();
  const auto open = reference::environment_irradiance(reference::Scene(desc), receivers, o);
  double open_mean = 0;
  for (const auto& r : open) open_mean += r.mean.y / open.size();

  BlockerAccumulation<N> acc;
  acc.set_blockers(one);
  const sh::CoeffsRgb<N> whole =
      sh::project_equirect<N>(env.map->rgb.data(), env.map->width, env.map->height);
  double sq_sh = 0, sq_key = 0, max_key = 0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 p = receivers[i].position, n = receivers[i].normal;
    const float sh_only = acc.irradiance(whole, p, n).y;
    const float key = acc.irradiance(components::sh_without(env, 1), p, n).y +
                      sun.irradiance.y * std::max(0.0f, glm::dot(n, sun.direction)) *
                          acc.key_light_visibility(p, sun.direction, sun.angular_radius);
    const double d_sh = (sh_only - ref[i].mean.y) / open_mean;
    const double d_key = (key - ref[i].mean.y) / open_mean;
    sq_sh += d_sh * d_sh, sq_key += d_key * d_key;
    max_key = std::max(max_key, std::abs(d_key));
  }
  const double rms_sh = std::sqrt(sq_sh / receivers.size());
  const double rms_key = std::sqrt(sq_key / receivers.size());
  std::printf(
      "one sphere, sky.exr: SH alone rel RMS %.2f%%, sun as key light %.2f%% (max %.2f%%)\n",
      100 * rms_sh, 100 * rms_key, 100 * max_key);
  EXPECT_LT(rms_key, 0.5 * rms_sh);
}

// key_light_visibility's geometry: a sphere straight towards the light hides it, one beside it
// does not, one whose cap's edge crosses the disc's centre hides the lens between them, inside a
// sphere nothing is seen, and a point light is in or out.
TEST(BlockerAccumulation, KeyLightVisibilityIsTheDiscTheSpheresLeave) {
  BlockerAccumulation<N> acc;
  const glm::vec3 up(0, 0, 1), p(0.0f);
  const float a = 0.05f;
  acc.set_blockers({{{0, 0, 10}, 1.0f}});  // cap 5.7 degrees, centred on the light
  EXPECT_EQ(acc.key_light_visibility(p, up, a), 0.0f);
  acc.set_blockers({{{5, 0, 10}, 1.0f}});  // 27 degrees aside
  EXPECT_EQ(acc.key_light_visibility(p, up, a), 1.0f);
  // Cap edge through the light's centre: the centre 10 m up and asin(1 / d) to the side.
  const float b = std::asin(1.0f / 10.0f);
  acc.set_blockers({{{10 * std::sin(b), 0, 10 * std::cos(b)}, 1.0f}});
  // The cap (radius 2a) curves away from the disc: the lens covers 44.7% of it (by hand).
  EXPECT_NEAR(acc.key_light_visibility(p, up, a), 0.553f, 0.005f);
  acc.set_blockers({{{0, 0, 0.5f}, 1.0f}});
  EXPECT_EQ(acc.key_light_visibility(p, up, a), 0.0f);  // inside
  acc.set_blockers({{{0.9f, 0, 10}, 1.0f}});  // cap edge 0.0106 rad from the light: a point is in
  EXPECT_EQ(acc.key_light_visibility(p, up, 0.0f), 0.0f);
  acc.set_blockers({{{1.1f, 0, 10}, 1.0f}});
  EXPECT_EQ(acc.key_light_visibility(p, up, 0.0f), 1.0f);
}

// Bands: the same scene at 3, 4 and 5 bands (what the SH truncation of V x cosine costs).
TEST(BlockerAccuracy, BandsThreeToFive) {
  const std::vector<WorldSphere> one = {{{0, 0, 2}, 1}};
  const Errors b3 = measure<3>(uniform_sky(), one, {});
  const Errors b4 = measure<4>(uniform_sky(), one, {});
  const Errors b5 = measure<5>(uniform_sky(), one, {});
  print("one sphere, uniform sky, 3 bands", b3);
  print("one sphere, uniform sky, 4 bands", b4);
  print("one sphere, uniform sky, 5 bands", b5);
  EXPECT_LT(b3.rms, 0.05f);   // measured 3.7%
  EXPECT_LT(b4.rms, 0.03f);   // 1.5%
  EXPECT_LT(b5.rms, 0.015f);  // 0.9%
  EXPECT_LT(b5.rms, b4.rms);  // the error falls as bands are added
  EXPECT_LT(b4.rms, b3.rms);
}

TEST(BlockerAccuracy, OverlappingSpheres) {
  const std::vector<WorldSphere> five = {{{0, 0, 2}, 1},
                                         {{0.8f, 0, 2.2f}, 0.8f},
                                         {{-0.7f, 0.3f, 1.8f}, 0.9f},
                                         {{0.2f, -0.6f, 2.5f}, 0.7f},
                                         {{0, 0.5f, 2.8f}, 0.6f}};
  BlockerSettings off, on;
  on.blocker.ratio = RatioAttenuation::kOn;
  const Errors a = measure(uniform_sky(), five, off);
  const Errors b = measure(uniform_sky(), five, on);
  print("five overlapping spheres, product", a);
  print("five overlapping spheres, ratio attenuation", b);
  EXPECT_LT(a.rms, 0.12f);
  EXPECT_LT(b.rms, 0.20f);
}

// The two logs of one blocker's visibility: [Giraud]'s log(eps) cap against [Ren06]'s SH log of
// the visibility with clipped eigenvalues (clipped_log_cap.h), one sphere and five overlapping.
TEST(BlockerAccuracy, CapEpsilonAgainstClippedEigenLog) {
  const std::vector<WorldSphere> one = {{{0, 0, 2}, 1}};
  const std::vector<WorldSphere> five = {{{0, 0, 2}, 1},
                                         {{0.8f, 0, 2.2f}, 0.8f},
                                         {{-0.7f, 0.3f, 1.8f}, 0.9f},
                                         {{0.2f, -0.6f, 2.5f}, 0.7f},
                                         {{0, 0.5f, 2.8f}, 0.6f}};
  BlockerSettings ren;
  ren.blocker.log = BlockerLog::kClippedEigen;
  const Errors a = measure(uniform_sky(), one, ren);
  const Errors b = measure(uniform_sky(), five, ren);
  const Errors c = measure(sky_map(), one, ren);
  print("one sphere, uniform sky, clipped eigen log", a);
  print("five overlapping spheres, clipped eigen log", b);
  print("one sphere, sky.exr, clipped eigen log", c);
  EXPECT_LT(a.rms, 0.01f);  // measured 0.48% (the eps cap: 1.49%)
  EXPECT_LT(b.rms, 0.06f);  // 3.6% (the eps cap: 3.1%)
  EXPECT_LT(c.rms, 0.25f);  // 20.4%: the sun's shadow, as with the eps cap
}

// [Giraud] sec. 4.2 admits where ratio attenuation fails: a small sphere near the receivers in
// line with a big one far above. Each is scaled by its own r / |c - p| (here about 0.3 and
// 0.3), so the shadow they cast together comes out too light.
TEST(BlockerAccuracy, RatioAttenuationFailsForSmallNearInLineWithBigFar) {
  PENUMBRA_STABILITY(
      "a small sphere near the receivers in line with a big one far above, ratio attenuation on",
      "each scaled by its own r / distance: the shadow comes out too light ([Giraud] sec. 4.2)",
      "ratio attenuation off (default) for such scenes");
  const std::vector<WorldSphere> in_line = {{{0, 0, 1.2f}, 0.35f}, {{0, 0, 12.0f}, 3.6f}};
  BlockerSettings off, on;
  on.blocker.ratio = RatioAttenuation::kOn;
  const Errors a = measure(uniform_sky(), in_line, off);
  const Errors b = measure(uniform_sky(), in_line, on);
  print("small near + big far in line, ratio off", a);
  print("small near + big far in line, ratio on", b);
  PENUMBRA_STABILITY_MEASURE("rel. RMS, ratio off", a.rms);
  PENUMBRA_STABILITY_MEASURE("rel. RMS, ratio on", b.rms);
  EXPECT_GT(b.rms, 1.2f * a.rms);  // the documented failure shows: measured 5.7% against 4.1%
  EXPECT_LT(a.rms, 0.06f);
}

// A local spherical light seen through a blocker: the light's cap as SH radiance, shadowed by
// the same visibility. Against the reference's light estimator, receivers on the ground under a
// light of radius 1.5 at height 6 and a sphere of radius 0.8 at height 3 beside the axis.
TEST(BlockerAccuracy, SphericalLightThroughABlocker) {
  const reference::SphereLight light{{0, 0, 6}, 1.5f, {4, 4, 4}, "light"};
  const WorldSphere blocker{{1, 0, 3}, 0.8f};
  reference::SceneDesc desc;
  desc.lights.push_back(light);
  desc.spheres.push_back({blocker.centre, blocker.radius, "blocker"});
  const reference::Scene with(desc);
  desc.spheres.clear();
  const reference::Scene open(desc);
  const std::vector<reference::Receiver> receivers = ground_receivers();
  reference::LightOptions o;
  o.samples = 4096;
  const auto ref = reference::light_irradiance(with, receivers, o);
  const auto ref_open = reference::light_irradiance(open, receivers, o);
  BlockerAccumulation<N> acc;
  acc.set_blockers({blocker});
  acc.set_lights({{light.center, light.radius, light.radiance}});
  BlockerAccumulation<N> no_blocker;
  no_blocker.set_lights({{light.center, light.radius, light.radiance}});
  const sh::CoeffsRgb<N> dark{};
  double mean = 0, sq = 0, sq_open = 0;
  float deepest = 0, ours_deepest = 0;
  for (const auto& r : ref_open) mean += r.mean.y / ref_open.size();
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const float e = acc.irradiance(dark, receivers[i].position, receivers[i].normal).y;
    const float e_open = no_blocker.irradiance(dark, receivers[i].position, receivers[i].normal).y;
    sq += (e - ref[i].mean.y) * (e - ref[i].mean.y);
    sq_open += (e_open - ref_open[i].mean.y) * (e_open - ref_open[i].mean.y);
    deepest = std::max(deepest, 1 - ref[i].mean.y / ref_open[i].mean.y);
    ours_deepest = std::max(ours_deepest, 1 - e / e_open);
  }
  const double rms = std::sqrt(sq / receivers.size()) / mean;
  const double rms_open = std::sqrt(sq_open / receivers.size()) / mean;
  std::printf(
      "spherical light, no blocker: rel RMS %.2f%%; through the blocker: %.2f%% "
      "(deepest shadow: reference %.0f%%, ours %.0f%%)\n",
      100 * rms_open, 100 * rms, 100 * deepest, 100 * ours_deepest);
  // Measured: 4.4% without the blocker, 32% through it. The eclipse is hard (the reference's
  // deepest shadow is total) and 16 coefficients blur it to 29% at most: the SH band limit of
  // the light's cap times the visibility, the limit of the method for small bright lights.
  EXPECT_GT(ours_deepest, 0.2f);  // the blocker does shadow the light
  EXPECT_LT(rms_open, 0.08);
  EXPECT_LT(rms, 0.4);
}

// [Giraud] fig. 6 in our terms: the exponentiated log-SH Phong lobe (eq. 27) against the SH
// Phong lobe itself, under a fixed smooth sky, no blockers; then a blocker across the reflected
// direction darkens the highlight.
TEST(BlockerAccuracy, PhongLogBrdfAgainstTheShLobe) {
  sh::CoeffsRgb<N> sky{};
  for (auto& c : sky) {
    c[0] = 3.0f;
    c[sh::index(1, 0)] = 1.5f;  // brighter towards +z
    c[sh::index(1, 1)] = 1.0f;  // and towards +x
    c[sh::index(2, 0)] = 0.5f;
  }
  const glm::vec3 p{0, 0, 0}, n{0, 0, 1}, view = glm::normalize(glm::vec3(-1, 0, 1));
  const glm::vec3 r = glm::normalize(glm::vec3(1, 0, 1));  // the reflected view direction
  // Worst relative error over the exponents, per floor: 0.01, 0.1 and the fitted one.
  float worst[3] = {};
  for (const float exponent : {1.0f, 4.0f, 16.0f, 64.0f}) {
    int k = 0;
    for (const float eps : {0.01f, 0.1f, 0.0f}) {  // 0: fitted to the exponent
      BlockerSettings s;
      s.phong_exponent = exponent;
      s.phong_epsilon = eps;
      BlockerAccumulation<N> acc(s);
      const float ours = acc.glossy_radiance(sky, p, n, view).y;
      const float exact =
          sh::dot<N>(sky[1], sh::rotate_zh<N>(BlockerAccumulation<N>::phong_zh(exponent), r));
      const float err = std::abs(ours - exact) / exact;
      std::printf("Phong r %4.0f, eps %.3f%s: log-SH %.4f, SH lobe %.4f, relative error %.1f%%\n",
                  exponent, eps > 0 ? eps : BlockerAccumulation<N>::fitted_phong_epsilon(exponent),
                  eps > 0 ? "" : " (fitted)", ours, exact, 100 * err);
      EXPECT_TRUE(std::isfinite(ours));
      worst[k] = std::max(worst[k], err);
      if (eps == 0.0f && exponent <= 4) {
        EXPECT_LT(err, 0.05f);  // measured 2.1%, 1.2%
      }
      ++k;
    }
  }
  // Each fixed floor fails somewhere (measured 88% for 0.01 at r 64, 26% for 0.1 at r 4); the
  // fitted one bounds the worst case (22%, at r 16: 4 bands cannot hold a sharp lobe's log).
  EXPECT_LT(worst[2], 0.25f);
  EXPECT_LT(worst[2], worst[0]);
  EXPECT_LT(worst[2], worst[1]);
  BlockerSettings s;
  s.phong_exponent = 4;
  BlockerAccumulation<N> acc(s);
  const float open = acc.glossy_radiance(sky, p, n, view).y;
  acc.set_blockers({{3.0f * r, 1.5f}});  // across the highlight
  EXPECT_LT(acc.glossy_radiance(sky, p, n, view).y, 0.8f * open);
  BlockerAccumulation<N> diffuse_only;
  EXPECT_THROW(diffuse_only.glossy_radiance(sky, p, n, view), std::logic_error);
}

// 001 sec. 4.2: log(eps) accumulated m times. The same sphere m times over one receiver (the
// exact visibility is that of one sphere): output finite, within [0, open sky], error printed.
TEST(BlockerStability, ManyOverlappingBlockersStayFiniteAndBounded) {
  PENUMBRA_STABILITY("1 to 1000 coincident blockers",
                     "finite; E within 0.1 of one sphere's shadow (without the depth limit, 6 or "
                     "more read as no shadow)",
                     "the accumulation's depth limit");
  const data::EnvironmentMap map = uniform_sky();
  const sh::CoeffsRgb<N> radiance = sh::project_equirect<N>(map.rgb.data(), map.width, map.height);
  const float open = std::numbers::pi_v<float>;
  for (const RatioAttenuation ratio : {RatioAttenuation::kOff, RatioAttenuation::kOn})
    for (const int m : {1, 2, 3, 4, 6, 10, 100, 1000}) {
      BlockerSettings s;
      s.blocker.ratio = ratio;
      BlockerAccumulation<N> acc(s);
      acc.set_blockers(std::vector<WorldSphere>(m, WorldSphere{{0.5f, 0, 2}, 1}));
      const glm::vec3 e = acc.irradiance(radiance, {0, 0, 0}, {0, 0, 1});
      std::printf("%4d blockers, ratio %s: E / open sky = %.3f\n", m,
                  ratio == RatioAttenuation::kOn ? "on " : "off", e.y / open);
      ASSERT_TRUE(std::isfinite(e.y)) << m;
      // Exact for any m: one sphere's shadow, E / open = 1 - sin^2 30deg cos 14deg = 0.77. The
      // depth limit keeps every m within 0.1 of it (without it, 6 or more read as no shadow at
      // all).
      if (m == 1000 && ratio == RatioAttenuation::kOff)
        PENUMBRA_STABILITY_MEASURE("|E / open - 0.77|, 1000 blockers",
                                   std::abs(e.y / open - 0.77f));
      EXPECT_NEAR(e.y / open, 0.77f, 0.1f) << m;
    }
}

TEST(BlockerStability, EpsilonSweepStaysFinite) {
  PENUMBRA_STABILITY("epsilon from 0.05 to 0.5 (one sphere)", "finite errors at every epsilon",
                     "-");
  const std::vector<WorldSphere> one = {{{0, 0, 2}, 1}};
  for (const float eps : {0.05f, 0.1f, 0.2f, 0.3f, 0.5f}) {
    BlockerSettings s;
    s.blocker.epsilon = eps;
    const Errors e = measure(uniform_sky(), one, s);
    char what[64];
    std::snprintf(what, sizeof what, "one sphere, epsilon %.2f", eps);
    print(what, e);
    EXPECT_TRUE(std::isfinite(e.rms));
  }
}

// What a receiver's sum cost: every candidate is viewed, only those that reach are added.
TEST(BlockerStability, PairCountsCountViewsAndAdds) {
  BlockerSettings s;
  s.blocker.min_sin = 0;  // every sphere is a candidate everywhere
  BlockerAccumulation<N> acc(s);
  acc.set_blockers({{{0, 0, 2}, 1}, {{0, 0, -5}, 1}, {{3, 0, 4}, 0.5f}});  // one below the plane
  BlockerAccumulation<N>::PairCounts c;
  acc.log_visibility({0, 0, 0}, {0, 0, 1}, &c);
  EXPECT_EQ(c.views, 3u);
  EXPECT_EQ(c.adds, 2u);
  EXPECT_EQ(c.depth_evaluations, 0u);  // two blockers cannot be deeper than max_depth 3
  acc.set_blockers(std::vector<WorldSphere>(10, WorldSphere{{0, 0, 2}, 1}));
  acc.log_visibility({0, 0, 0}, {0, 0, 1}, &c);
  EXPECT_EQ(c.views, 13u);
  EXPECT_EQ(c.adds, 12u);
  EXPECT_EQ(c.depth_evaluations, 10u);
}

TEST(BlockerStability, BadInputIsNamed) {
  PENUMBRA_STABILITY("a NaN or negative-radius sphere, epsilon 0, a NaN receiver",
                     "std::invalid_argument naming the sphere or receiver", "-");
  BlockerAccumulation<N> acc;
  try {
    acc.set_blockers({{{0, 0, 1}, 1}, {{0, NAN, 1}, 1}});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sphere 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(acc.set_blockers({{{0, 0, 1}, -1}}), std::invalid_argument);
  EXPECT_THROW(acc.set_blockers({{{0, 0, 1}, INFINITY}}), std::invalid_argument);
  EXPECT_THROW(BlockerAccumulation<N>(BlockerSettings{{0.0f}}), std::invalid_argument);
  acc.set_blockers({{{0, 0, 1}, 1}});
  const sh::CoeffsRgb<N> radiance{};
  std::vector<glm::vec3> points = {{0, 0, 0}, {INFINITY, 0, 0}}, normals(2, {0, 0, 1}), out(2);
  try {
    acc.shade(radiance, points, normals, {}, out);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("receiver 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
