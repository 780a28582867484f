// Accuracy of probe-cloud interpolation ([Cupisz12], [Sukys14] sec. 3.2) against the reference
// integrator (engine/reference), in the scene of probe_accuracy_scene.h: a ground plane, two
// boxes, a smooth sky with a broad bright lobe. Probe SH are the reference's irradiance SH at
// the probe (3 bands by default; 2 and 4 too); the interpolated irradiance at random query
// points, for the six axis normals, is compared with environment_irradiance there. Errors
// (luminance): rel RMS = sqrt(sum d^2 / sum ref^2), max = max |d| / RMS(ref), per region of the
// query (interior, a tetrahedron on the hull: edge, an outer cell: outside). The measured numbers
// are printed; bounds sit above them with headroom (the reference's noise is printed too).
//
// And the SH axis convention (godotengine/godot #94824: probes applied mirrored): a probe cloud
// lit from one side gives light on that side, with band 1 ordered (y, z, x) as engine/sh, the
// sky rotation as the reference and the renderer's sky pass (shaders/sky.glsl) read it, and
// world-space normals as the vertex lighting (blocker_systems.cpp's normal matrix) uses them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "common/stability.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"
#include "probe_accuracy_scene.h"

namespace penumbra::probe_cloud::accuracy {
namespace {

constexpr int kQueries = 800;
constexpr int kReferenceSamples = 4096;

struct Fixture {
  data::EnvironmentMap sky = lobe_sky();
  reference::Scene scene = make_scene(sky);
  Queries queries = make_queries(scene, kQueries, kReferenceSamples, 2024);
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void print(const char* name, const CloudErrors& e) {
  std::printf("%-22s probes %5zu tets %6zu |", name, e.probes, e.tetrahedra);
  for (int k = 0; k < 3; ++k)
    std::printf(" %s (%d): %.2f%% max %.1f%% |", kRegionNames[k], e.region[k].points,
                100 * e.region[k].rel_rms, 100 * e.region[k].max_rel);
  std::printf(" all: %.2f%% max %.1f%% (reference noise %.2f%%)\n", 100 * e.all.rel_rms,
              100 * e.all.max_rel, 100 * e.all.noise);
}

CloudErrors measure(const char* name, const std::vector<glm::vec3>& points, int bands) {
  const data::ProbeCloud cloud = make_cloud(fixture().scene, points, bands);
  EXPECT_TRUE(validate_probe_cloud(cloud).ok()) << name;
  const CloudErrors e = cloud_errors(cloud, fixture().queries);
  print(name, e);
  return e;
}

TEST(ProbeAccuracy, ReferenceNoiseIsSmall) {
  const CloudErrors e =
      cloud_errors(make_cloud(fixture().scene, grid_points(2.0f), 3), fixture().queries);
  // The reference's own standard error, relative: the floor under every number below.
  EXPECT_LT(e.all.noise, 0.01);
  for (int k = 0; k < 3; ++k) EXPECT_GT(e.region[k].points, 40) << kRegionNames[k];
}

TEST(ProbeAccuracy, GridSpacings) {
  // Measured (interior / edge / outside rel RMS): 2 m 9.0 / 8.6 / 3.1%, 1 m 7.0 / 4.1 / 2.7%,
  // 0.5 m 3.6 / 1.7 / 1.9%; the max (71-90%, 40% at 0.5 m) sits at queries a few centimetres
  // from a box wall, lit, whose tetrahedron reaches probes in the wall's shadow.
  const CloudErrors g2 = measure("grid 2 m, 3 bands", grid_points(2.0f), 3);
  const CloudErrors g1 = measure("grid 1 m, 3 bands", grid_points(1.0f), 3);
  const CloudErrors g05 = measure("grid 0.5 m, 3 bands", grid_points(0.5f), 3);
  // Finer grids follow the boxes' shadows more closely.
  EXPECT_LT(g1.region[0].rel_rms, g2.region[0].rel_rms);
  EXPECT_LT(g05.region[0].rel_rms, g1.region[0].rel_rms);
  EXPECT_LT(g05.all.rel_rms, g1.all.rel_rms);
  EXPECT_LT(g1.all.rel_rms, g2.all.rel_rms);
  EXPECT_LT(g2.region[0].rel_rms, 0.14);
  EXPECT_LT(g1.region[0].rel_rms, 0.11);
  EXPECT_LT(g05.region[0].rel_rms, 0.06);
  EXPECT_LT(g05.region[1].rel_rms, 0.03);
  EXPECT_LT(g05.all.max_rel, 0.6);
}

TEST(ProbeAccuracy, BandCounts) {
  // Measured (all queries): 2 bands 14.5%, 3 bands 4.0%, 4 bands 4.0%.
  const CloudErrors b2 = measure("grid 1 m, 2 bands", grid_points(1.0f), 2);
  const CloudErrors b3 = measure("grid 1 m, 3 bands", grid_points(1.0f), 3);
  const CloudErrors b4 = measure("grid 1 m, 4 bands", grid_points(1.0f), 4);
  EXPECT_LT(b3.all.rel_rms, 0.5 * b2.all.rel_rms);
  // The clamped cosine has no band-3 part ([Ramamoorthi01]): 4 bands add only the projection's
  // noise.
  EXPECT_NEAR(b4.all.rel_rms, b3.all.rel_rms, 0.005);
  EXPECT_LT(b2.all.rel_rms, 0.22);
  EXPECT_LT(b3.all.rel_rms, 0.06);
}

// The lowest interpolated irradiance (luminance) over the queries and the six normals, relative
// to the RMS reference irradiance.
double lowest_interpolated(const data::ProbeCloud& cloud) {
  const ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(cloud));
  const Queries& q = fixture().queries;
  double lo = 0, r2 = 0;
  for (float r : q.reference) r2 += double(r) * r;
  for (const glm::vec3& p : q.points) {
    const ProbeSh s = walk.interpolate(walk.locate(p, kNoCell));
    for (const glm::vec3& n : axis_normals()) lo = std::min(lo, double(interpolated(s, n)));
  }
  return lo / std::sqrt(r2 / q.reference.size());
}

TEST(ProbeAccuracy, WindowedAgainstRinging) {
  // The probes' irradiance windowed at the cloud's band count (sh::dering_irradiance, the issue's
  // "windowed against ringing"). The black ground makes every probe's irradiance fall to ~0 for
  // downward normals, where the cut SH ring negative, so the window acts on most probes: it
  // removes the negative lobes and costs accuracy. Measured (all queries): 3 bands 4.0% raw,
  // 6.4% windowed; 2 bands 14.5% raw, 21.9% windowed; lowest interpolated irradiance -2.9% of
  // the RMS raw, >= 0 windowed.
  const data::ProbeCloud raw_cloud = make_cloud(fixture().scene, grid_points(1.0f), 3);
  const data::ProbeCloud win_cloud = make_cloud(fixture().scene, grid_points(1.0f), 3, true);
  const CloudErrors raw = cloud_errors(raw_cloud, fixture().queries);
  const CloudErrors win = cloud_errors(win_cloud, fixture().queries);
  print("grid 1 m, 3 bands", raw);
  print("grid 1 m, 3, windowed", win);
  const CloudErrors win2 =
      cloud_errors(make_cloud(fixture().scene, grid_points(1.0f), 2, true), fixture().queries);
  print("grid 1 m, 2, windowed", win2);
  const double low_raw = lowest_interpolated(raw_cloud), low_win = lowest_interpolated(win_cloud);
  std::printf("lowest interpolated irradiance / RMS reference: raw %.4f, windowed %.4f\n", low_raw,
              low_win);
  EXPECT_LT(low_raw, 0.0);    // the cut SH ring below zero somewhere
  EXPECT_GE(low_win, -1e-3);  // the window's tolerance (1e-4 of the mean) and the walk's weights
  EXPECT_LE(low_win, 0.05);
  EXPECT_LT(win.all.rel_rms, 0.09);
  EXPECT_LT(win2.all.rel_rms, 0.28);
}

TEST(ProbeAccuracy, RandomAndHandPlacedClouds) {
  // Measured interior: random 400 points 6.0%, hand-placed (64 probes) 10.2%.
  const CloudErrors r = measure("random 400, 3 bands", random_points(400, 99), 3);
  const CloudErrors h = measure("hand-placed, 3 bands", hand_placed_points(), 3);
  EXPECT_LT(r.region[0].rel_rms, 0.09);
  EXPECT_LT(h.region[0].rel_rms, 0.15);
  EXPECT_LT(r.all.rel_rms, 0.06);
  EXPECT_LT(h.all.rel_rms, 0.08);
}

TEST(ProbeAccuracy, HullEdgeAndOutside) {
  PENUMBRA_STABILITY(
      "queries at the hull's edge and 1.5 m outside it",
      "a convex mix of three hull probes: wrong where the light past the hull differs",
      "probes beyond where objects go");
  // Outside the hull the [Cupisz12] extrapolation is a convex mix of three hull probes: wrong
  // where the light past the hull differs from the hull's (measured max 67-113% of the RMS
  // irradiance, at queries 1.5 m past the hull beside a box), small on average in this open sky.
  // Measured edge / outside: grid 1 m 4.1 / 2.7%, random 400 3.4 / 3.6%.
  const CloudErrors g = measure("grid 1 m, 3 bands", grid_points(1.0f), 3);
  PENUMBRA_STABILITY_MEASURE("rel. RMS at the edge, grid 1 m", g.region[1].rel_rms);
  PENUMBRA_STABILITY_MEASURE("rel. RMS outside, grid 1 m", g.region[2].rel_rms);
  EXPECT_LT(g.region[1].rel_rms, 0.07);
  EXPECT_LT(g.region[2].rel_rms, 0.045);
  EXPECT_LT(g.region[2].max_rel, 1.1);
  const CloudErrors r = measure("random 400, 3 bands", random_points(400, 99), 3);
  EXPECT_LT(r.region[1].rel_rms, 0.055);
  EXPECT_LT(r.region[2].rel_rms, 0.055);
  EXPECT_LT(r.region[2].max_rel, 1.7);
}

// --- SH axis convention ------------------------------------------------------------------------

// What the renderer's sky pass shows in world direction d (shaders/sky.glsl, variant 1): the
// texel at u = (atan(d.y, d.x) - rotation) / 2 pi (wrapped), v = acos(d.z) / pi.
float sky_pass_radiance(const data::EnvironmentMap& map, float rotation, const glm::vec3& d) {
  float u = (std::atan2(d.y, d.x) - rotation) / (2 * std::numbers::pi_v<float>);
  u -= std::floor(u);
  const float v = std::acos(std::clamp(d.z, -1.0f, 1.0f)) / std::numbers::pi_v<float>;
  const int x = std::min(static_cast<int>(u * map.width), map.width - 1);
  const int y = std::min(static_cast<int>(v * map.height), map.height - 1);
  return map.texel(x, y)[1];
}

struct Lit {
  glm::vec3 direction;  // where the light comes from, in the world
  float rotation;       // the environment's rotation_z
};

class ProbeShConvention : public testing::TestWithParam<Lit> {};

TEST_P(ProbeShConvention, LightOnTheLitSide) {
  const Lit lit = GetParam();
  // The map's bright cap sits where, rotated by `rotation`, it lights from lit.direction.
  const glm::vec3 in_map =
      glm::mat3(glm::rotate(glm::mat4(1.0f), -lit.rotation, {0, 0, 1})) * lit.direction;
  const data::EnvironmentMap map = make_sky(
      [&](const glm::vec3& d) { return glm::vec3(glm::dot(d, in_map) > 0.8f ? 1.0f : 0.01f); },
      "cap");
  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{map, lit.rotation};
  const reference::Scene scene(desc);  // no occluders
  // The renderer's sky pass shows the cap in the world direction of the light.
  ASSERT_EQ(sky_pass_radiance(map, lit.rotation, lit.direction), 1.0f);
  ASSERT_EQ(sky_pass_radiance(map, lit.rotation, -lit.direction), 0.01f);

  std::vector<glm::vec3> probes;
  for (int i = 0; i < 8; ++i) probes.emplace_back(i & 1 ? 2 : 0, i & 2 ? 2 : 0, i & 4 ? 2 : 0);
  probes.emplace_back(1.2f, 0.9f, 1.1f);
  const data::ProbeCloud cloud = make_cloud(scene, probes, 3);
  const ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(cloud));
  const glm::vec3 p(0.7f, 1.3f, 0.6f);
  const ProbeSh s = walk.interpolate(walk.locate(p, kNoCell));

  // Band 1 is (y, z, x): its vector (c3, c1, c2) points at the light.
  const glm::vec3 band1(s[1][3], s[1][1], s[1][2]);
  EXPECT_GT(glm::dot(glm::normalize(band1), lit.direction), 0.99f)
      << band1.x << " " << band1.y << " " << band1.z;

  // The irradiance for a normal facing the light against the reference there, and facing away.
  std::vector<reference::Receiver> rx{{p, lit.direction}, {p, -lit.direction}};
  reference::IrradianceOptions o;
  o.samples = 4096;
  const auto ref = reference::environment_irradiance(scene, rx, o);
  const float lit_side = sh::evaluate<4>(s[1], lit.direction);
  const float dark_side = sh::evaluate<4>(s[1], -lit.direction);
  std::printf(
      "light from (%.0f, %.0f, %.0f), rotation %.2f: E(lit side) %.4f (reference %.4f), "
      "E(away) %.4f (reference %.4f)\n",
      lit.direction.x, lit.direction.y, lit.direction.z, lit.rotation, lit_side, ref[0].mean.y,
      dark_side, ref[1].mean.y);
  // The cap's sharp rim has irradiance past 3 bands (l = 4, 6 of the clamped cosine): measured
  // 1.6-4.0% on the lit side, 2.7% of it on the far side (ringing).
  EXPECT_NEAR(lit_side, ref[0].mean.y, 0.06f * ref[0].mean.y);
  EXPECT_LT(dark_side, 0.1f * lit_side);
  EXPECT_NEAR(dark_side, ref[1].mean.y, 0.05f * ref[0].mean.y);

  // Vertex lighting reads world-space normals (normal matrix of the entity's transform): a mesh
  // turned 90 degrees about z is lit on the face whose local normal the turn brings to the light.
  const glm::mat3 turn =
      glm::mat3(glm::rotate(glm::mat4(1.0f), std::numbers::pi_v<float> / 2, glm::vec3(0, 0, 1)));
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(turn));
  const glm::vec3 local = glm::transpose(turn) * lit.direction;
  EXPECT_NEAR(sh::evaluate<4>(s[1], normal_matrix * local), lit_side, 1e-4f * lit_side);
  if (std::abs(lit.direction.z) < 0.5f) {
    EXPECT_LT(sh::evaluate<4>(s[1], local), 0.75f * lit_side);  // not the unturned normal
  }
}

INSTANTIATE_TEST_SUITE_P(Axes, ProbeShConvention,
                         testing::Values(Lit{{1, 0, 0}, 0.0f}, Lit{{0, 1, 0}, 0.0f},
                                         Lit{{0, 0, 1}, 0.0f}, Lit{{-1, 0, 0}, 0.0f},
                                         Lit{{0, 1, 0}, std::numbers::pi_v<float> / 2},
                                         Lit{{1, 0, 0}, 1.0f}));

}  // namespace
}  // namespace penumbra::probe_cloud::accuracy
