// Stability tests of the probe-cloud build (issue 12, "Stability"): each builds a cloud that the
// validation pass must accept, and asserts a behaviour that could fail.
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

namespace penumbra::probe_cloud {
namespace {

std::string errors(const ProbeCloudValidation& v) {
  std::string s;
  for (const std::string& e : v.errors) s += e + "\n";
  return s;
}

#define EXPECT_VALID(cloud)                                      \
  do {                                                           \
    const ProbeCloudValidation v_ = validate_probe_cloud(cloud); \
    EXPECT_TRUE(v_.ok()) << errors(v_);                          \
  } while (0)

std::vector<glm::vec3> random_points(std::size_t n, unsigned seed, float size = 10.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, size);
  std::vector<glm::vec3> p(n);
  for (glm::vec3& q : p) q = {u(rng), u(rng), u(rng)};
  return p;
}

TEST(ProbeCloudBuild, Grid10x10x10MaximallyCospherical) {
  PENUMBRA_STABILITY("a 10x10x10 grid far from the origin (every cube cospherical)",
                     "a valid cloud: 4,348 tetrahedra, 972 outer cells",
                     "exact predicates with symbolic perturbation");
  std::vector<glm::vec3> p;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) p.push_back(glm::vec3(i, j, k) * 2.0f + glm::vec3(100, 50, 3));
  ProbeCloudBuildReport report;
  const data::ProbeCloud cloud = build_probe_cloud(p, {}, {}, &report);
  EXPECT_VALID(cloud);
  EXPECT_EQ(report.merged_duplicates, 0u);
  EXPECT_EQ(report.outer_cells, 6u * 81 * 2);
  EXPECT_GE(report.tetrahedra, 729u * 5);
  EXPECT_LE(report.tetrahedra, 729u * 6);
  RecordProperty("tetrahedra", static_cast<int>(report.tetrahedra));
  std::printf("10x10x10 grid: %zu tetrahedra, %zu outer cells, %.3f ms\n", report.tetrahedra,
              report.outer_cells, report.seconds * 1e3);
  // A grid's flat hull faces: the normals of probes inside a face are the face normal.
  EXPECT_FLOAT_EQ(cloud.hull_normals[0 * 100 + 5 * 10 + 5].x, -1.0f);  // the x = min face
}

TEST(ProbeCloudBuild, RandomPointsWithExactAndNearDuplicates) {
  PENUMBRA_STABILITY("random points with exact and sub-millimetre duplicates",
                     "duplicates within the merge distance merged, 2 mm apart kept; valid",
                     "merge distance");
  std::vector<glm::vec3> p = random_points(1000, 11);
  std::vector<float> sh(p.size() * 27, 1.0f);
  for (int i = 0; i < 50; ++i) p.push_back(p[static_cast<std::size_t>(i * 7)]);  // exact
  for (int i = 0; i < 30; ++i) {                                                 // within 0.4 mm
    p.push_back(p[static_cast<std::size_t>(i * 11 + 3)] + glm::vec3(2e-4f, -2e-4f, 1e-4f));
  }
  p.push_back(p[500] + glm::vec3(2e-3f, 0, 0));  // 2 mm: kept
  sh.resize(p.size() * 27, 3.0f);
  ProbeCloudBuildReport report;
  const data::ProbeCloud cloud = build_probe_cloud(p, sh, {}, &report);
  EXPECT_VALID(cloud);
  EXPECT_EQ(report.input_points, 1081u);
  EXPECT_EQ(report.merged_duplicates, 80u);
  EXPECT_EQ(cloud.probe_count(), 1001u);
  ASSERT_EQ(report.kept_index.size(), p.size());
  EXPECT_EQ(report.kept_index[1000], report.kept_index[0]);
  // Merged SH is the mean: probe 0 had 1 and its duplicate 3.
  EXPECT_FLOAT_EQ(cloud.probe_sh(report.kept_index[0])[0], 2.0f);
  EXPECT_FLOAT_EQ(cloud.probe_sh(report.kept_index[1])[0], 1.0f);
}

TEST(ProbeCloudBuild, CoplanarAndCollinearSetsHaveNoCells) {
  PENUMBRA_STABILITY("coplanar, collinear and tilted-plane probe sets",
                     "no cells (no error); one probe off the plane makes a valid thin cloud", "-");
  std::vector<glm::vec3> plane, line;
  for (int i = 0; i < 100; ++i) {
    plane.push_back({float(i % 10), float(i / 10), 0.0f});
    line.push_back(glm::vec3(1, 2, 3) * float(i));
  }
  // A tilted plane: exactly coplanar in floats (integer coordinates on x + y + z = 30).
  std::vector<glm::vec3> tilted;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) tilted.push_back({float(i), float(j), float(30 - i - j)});
  for (const auto* set : {&plane, &line, &tilted}) {
    const data::ProbeCloud cloud = build_probe_cloud(*set, {});
    EXPECT_VALID(cloud);
    EXPECT_TRUE(cloud.cells.empty());
    EXPECT_EQ(cloud.probe_count(), 100u);
  }
  // One probe off the tilted plane makes a valid, thin tetrahedralization.
  tilted.push_back({3.0f, 3.0f, 24.5f});
  const data::ProbeCloud cloud = build_probe_cloud(tilted, {});
  EXPECT_VALID(cloud);
  EXPECT_GT(cloud.inner_count, 0u);
}

TEST(ProbeCloudBuild, FourCoplanarPoints) {
  PENUMBRA_STABILITY("four coplanar probes; one lifted 1 mm",
                     "no cells, valid; lifted: one thin tetrahedron, 5 cells, valid", "-");
  const std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const data::ProbeCloud cloud = build_probe_cloud(p, {});
  EXPECT_VALID(cloud);
  EXPECT_TRUE(cloud.cells.empty());
  const std::vector<glm::vec3> q{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-3f}};
  const data::ProbeCloud one = build_probe_cloud(q, {});
  EXPECT_VALID(one);
  EXPECT_EQ(one.inner_count, 1u);
  EXPECT_EQ(one.cells.size(), 5u);
}

TEST(ProbeCloudBuild, ZeroToThreeProbes) {
  PENUMBRA_STABILITY("0 to 3 probes", "a valid cloud with no cells", "-");
  const std::vector<glm::vec3> all{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (std::size_t n = 0; n <= 3; ++n) {
    const std::vector<float> sh(n * 12, 0.5f);
    ProbeCloudBuildSettings settings;
    settings.bands = 2;
    const data::ProbeCloud cloud =
        build_probe_cloud(std::span(all).first(n), sh, settings, nullptr);
    EXPECT_VALID(cloud);
    EXPECT_EQ(cloud.probe_count(), n);
    EXPECT_TRUE(cloud.cells.empty());
    EXPECT_EQ(cloud.sh.size(), n * 12);
  }
}

TEST(ProbeCloudBuild, KilometreSceneAtOneMetreAndFarProbes) {
  PENUMBRA_STABILITY(
      "a 1 km strip at 1 m spacing at kilometre coordinates plus probes 100 m apart (godot #82642)",
      "a valid cloud, no false duplicates", "exact predicates");
  // A 1 km strip of the terrain-following layer at 1 m spacing (two layers 1 m apart, 1000 x 3
  // probes each), at kilometre coordinates, plus probes 100 m apart above it (godot #82642).
  std::vector<glm::vec3> p;
  for (int layer = 0; layer < 2; ++layer)
    for (int x = 0; x < 1000; ++x)
      for (int y = 0; y < 3; ++y) {
        const float h = 0.02f * float(x % 7);  // gentle bumps, not a perfect grid
        p.push_back({4000.0f + float(x), -2000.0f + float(y), 500.0f + h + float(layer)});
      }
  for (int i = 0; i < 10; ++i) p.push_back({4000.0f + 100.0f * float(i), -1999.0f, 600.0f});
  ProbeCloudBuildReport report;
  const data::ProbeCloud cloud = build_probe_cloud(p, {}, {}, &report);
  EXPECT_VALID(cloud);
  EXPECT_EQ(report.merged_duplicates, 0u);
  EXPECT_GT(report.tetrahedra, p.size());
  std::printf("1 km strip: %zu probes, %zu tetrahedra, %zu outer cells, %.1f ms\n", p.size(),
              report.tetrahedra, report.outer_cells, report.seconds * 1e3);
}

TEST(ProbeCloudBuild, RejectsNonFinitePositionsNamingTheIndex) {
  PENUMBRA_STABILITY("a NaN or infinite probe position; SH of the wrong size",
                     "std::invalid_argument naming the probe index", "-");
  std::vector<glm::vec3> p = random_points(20, 2);
  p[13].y = std::numeric_limits<float>::quiet_NaN();
  try {
    build_probe_cloud(p, {});
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("13"), std::string::npos) << e.what();
  }
  p[13].y = 0;
  p[7].z = -std::numeric_limits<float>::infinity();
  try {
    build_probe_cloud(p, {});
    FAIL() << "infinity accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("7"), std::string::npos) << e.what();
  }
  p[7].z = 0;
  EXPECT_THROW(build_probe_cloud(p, std::vector<float>(5)), std::invalid_argument);
  ProbeCloudBuildSettings bad;
  bad.bands = 5;
  EXPECT_THROW(build_probe_cloud(p, {}, bad), std::invalid_argument);
}

TEST(ProbeCloudBuild, TetrahedronCountIsLinearInRandomPoints) {
  double ratios[2] = {0, 0};
  int i = 0;
  for (std::size_t n : {2000u, 20000u}) {
    ProbeCloudBuildReport report;
    const data::ProbeCloud cloud = build_probe_cloud(random_points(n, 5), {}, {}, &report);
    if (n == 2000u) EXPECT_VALID(cloud);
    ratios[i++] = double(report.tetrahedra) / double(n);
    std::printf("%zu random points: %zu tetrahedra (%.2f per point), %.1f ms\n", n,
                report.tetrahedra, ratios[i - 1], report.seconds * 1e3);
  }
  EXPECT_GT(ratios[1], 6.0);
  EXPECT_LT(ratios[1], 7.0);
  EXPECT_NEAR(ratios[0], ratios[1], 0.5);  // grows towards ~6.7 as the hull's share shrinks
}

}  // namespace
}  // namespace penumbra::probe_cloud
