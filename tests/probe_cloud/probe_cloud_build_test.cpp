// Stability tests of the probe-cloud build (issue 12, "Stability"): each builds a cloud that the
// validation pass must accept, and asserts a behaviour that could fail.
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

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

TEST(ProbeCloudBuild, SnapToBoxFacesMovesOnlyCoordinatesNearTheFaces) {
  std::vector<glm::vec3> p = {{0, 0, 0},        {10, 5, 2}, {1e-5f, 3, 1}, {9.9999f, 5 - 2e-5f, 1},
                              {5, 2.5f, 1e-3f}, {4, 2, 1}};
  // The shortest side is 2 (z): the tolerance 1e-4 * 2 = 2e-4.
  EXPECT_EQ(snap_to_box_faces(p, 1e-4), 3u);
  EXPECT_EQ(p[2].x, 0.0f);
  EXPECT_EQ(p[3].x, 10.0f);
  EXPECT_EQ(p[3].y, 5.0f);
  EXPECT_EQ(p[4].z, 1e-3f);  // 5e-4 of the shortest side: left where it is
  EXPECT_EQ(p[5], glm::vec3(4, 2, 1));
  EXPECT_EQ(snap_to_box_faces(p, 1e-4), 0u);  // nothing left to move
  p[2].x = 1e-5f;
  EXPECT_EQ(snap_to_box_faces(p, 0.0), 0u);
  EXPECT_EQ(snap_to_box_faces(p, -1e-4), 0u);
  EXPECT_EQ(snap_to_box_faces(p, std::numeric_limits<double>::quiet_NaN()), 0u);
  EXPECT_EQ(p[2].x, 1e-5f);
  std::vector<glm::vec3> flat = {{0, 0, 0}, {1, 0, 0}, {1e-7f, 1, 0}};  // z side 0: tolerance 0
  EXPECT_EQ(snap_to_box_faces(flat, 1e-4), 0u);
  EXPECT_EQ(flat[2].x, 1e-7f);
}

// A grid of 8 x 6 x 4 probes 1 m apart (x in [-3.5, 3.5]) whose every coordinate is moved by up
// to 10^-6 m, as rounding or another compiler can leave a placement, with a wall at x = 0: the
// probes at x < 0 see 1 (every coefficient), those at x > 0 see 0. Queries 0.2 m above the top
// face, 1.5-3 m on the dark side of the wall, are in outer cells.
TEST(ProbeCloudBuild, GridMovedByAHairKeepsFlatHullFaces) {
  PENUMBRA_STABILITY(
      "a 1 m grid with every coordinate moved by up to 1e-6 m, lit on one side of a wall",
      "flat hull faces: the outer cells on the dark side read the dark side only",
      "coordinates within 1e-4 of the shortest side of the box's faces moved onto them");
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> hair(-1e-6f, 1e-6f);
  std::vector<glm::vec3> p;
  std::vector<float> sh;
  constexpr int kCoeffs = 3 * data::kProbeDefaultBands * data::kProbeDefaultBands;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) {
        glm::vec3 q(-3.5f + float(x), -2.5f + float(y), 0.5f + float(z));
        for (int k = 0; k < 3; ++k) q[k] += hair(rng);
        p.push_back(q);
        sh.insert(sh.end(), kCoeffs, x < 4 ? 1.0f : 0.0f);
      }
  struct Reading {
    double longest_hull_edge = 0, leak = 0;
    std::size_t snapped = 0;
  };
  auto read = [&](float face_snap) {
    ProbeCloudBuildSettings settings;
    settings.face_snap = face_snap;
    ProbeCloudBuildReport report;
    auto cloud =
        std::make_shared<const data::ProbeCloud>(build_probe_cloud(p, sh, settings, &report));
    EXPECT_VALID(*cloud);
    Reading r;
    r.snapped = report.snapped_coordinates;
    for (std::size_t c = cloud->inner_count; c < cloud->cells.size(); ++c)
      for (int i = 0; i < 3; ++i) {
        const glm::vec3 a = cloud->positions[static_cast<std::size_t>(cloud->cells[c].vertices[i])];
        const glm::vec3 b =
            cloud->positions[static_cast<std::size_t>(cloud->cells[c].vertices[(i + 1) % 3])];
        r.longest_hull_edge = std::max(r.longest_hull_edge, double(glm::length(a - b)));
      }
    const ProbeTetWalk walk(cloud);
    for (float x = 1.5f; x <= 3.0f; x += 0.25f)
      for (float y = -2.25f; y <= 2.25f; y += 0.5f) {
        const ProbeWalkResult at = walk.locate({x, y, 3.7f}, -1);
        EXPECT_TRUE(cloud->cells[static_cast<std::size_t>(at.cell)].outer());
        r.leak = std::max(r.leak, double(walk.interpolate(at)[0][0]));
      }
    return r;
  };
  const Reading snapped = read(1e-4f), unsnapped = read(0.0f);
  std::printf(
      "hull edges up to %.2f m, dark side reads %.3f (%zu coordinates snapped); without "
      "the snap %.2f m and %.3f\n",
      snapped.longest_hull_edge, snapped.leak, snapped.snapped, unsnapped.longest_hull_edge,
      unsnapped.leak);
  EXPECT_GT(snapped.snapped, 100u);           // the outer layer's coordinates that were off
  EXPECT_LT(snapped.longest_hull_edge, 1.5);  // a face diagonal: sqrt(2)
  EXPECT_LT(snapped.leak, 1e-6);
  // What the snap prevents: slivers across the face, the lit side extrapolated onto the dark.
  EXPECT_GT(unsnapped.longest_hull_edge, 3.0);
  EXPECT_GT(unsnapped.leak, 0.05);
  PENUMBRA_STABILITY_MEASURE("dark-side outer cells' value (lit = 1)", snapped.leak);
  PENUMBRA_STABILITY_MEASURE("the same without the snap", unsnapped.leak);
}

}  // namespace
}  // namespace penumbra::probe_cloud
