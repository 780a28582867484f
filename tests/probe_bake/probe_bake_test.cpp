// The bake (probe_bake.h): stability cases, validity, determinism, accuracy against the
// reference integrator in the room scene (docs/probe_bake.md, "Accuracy").
#include "penumbra/systems/probe_bake/probe_bake.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"
#include "room_accuracy_points.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

BakeScene parse(const std::string& json) {
  return parse_bake_scene(json, "test.json", kData);
}

bool all_finite(const data::ProbeCloud& c) {
  for (float v : c.sh)
    if (!std::isfinite(v)) return false;
  return true;
}
bool all_zero(const data::ProbeCloud& c) {
  for (float v : c.sh)
    if (v != 0) return false;
  return true;
}

BakeSettings fast() {
  BakeSettings s;
  s.samples = 64;
  return s;
}

TEST(ProbeBake, EmptySceneIsBlackAndValid) {
  PENUMBRA_STABILITY("an empty scene (no geometry, no light)",
                     "27 probes, all SH exactly 0, a valid cloud", "-");
  const BakeScene s = parse(R"({"probes": {"min": [0,0,0], "max": [2,2,2], "spacing": 1}})");
  BakeReport r;
  const data::ProbeCloud c = bake_probe_cloud(s, fast(), &r);
  EXPECT_EQ(c.probe_count(), 27u);
  EXPECT_TRUE(all_zero(c));
  EXPECT_TRUE(r.valid_cloud);
  EXPECT_EQ(r.valid, 27u);
  EXPECT_NO_THROW(assets::encode_probe_cloud_file(c));
}

TEST(ProbeBake, NoLightIsBlack) {
  PENUMBRA_STABILITY("the room without its lamp", "all SH exactly 0, valid, none black by validity",
                     "-");
  // The room without its lamp: geometry, albedo, nothing emits.
  BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  s.desc.lights.clear();
  BakeReport r;
  const data::ProbeCloud c = bake_probe_cloud(s, fast(), &r);
  EXPECT_TRUE(all_zero(c));
  EXPECT_TRUE(r.valid_cloud);
  EXPECT_EQ(r.black, 0u);
}

// A probe volume wholly inside a 100 m box: every probe invalid, none can be pushed out
// (max offset 0.5 spacing), no valid neighbour: the documented fallback is black probes in a
// valid cloud.
TEST(ProbeBake, AllProbesInvalidFallBackToBlack) {
  PENUMBRA_STABILITY("a probe volume wholly inside a 100 m box (all probes invalid)",
                     "black probes (fallback), back-face share 1.0 each, a valid cloud", "-");
  const BakeScene s = parse(R"({
    "geometry": [{"kind": "box", "center": [0,0,0], "size": [100,100,100], "albedo": [0.5,0.5,0.5]}],
    "lights": [{"center": [0,0,80], "radius": 1, "radiance": [10,10,10]}],
    "probes": {"min": [-2,-2,-2], "max": [2,2,2], "spacing": 1}})");
  BakeReport r;
  const data::ProbeCloud c = bake_probe_cloud(s, fast(), &r);
  EXPECT_EQ(r.black, 125u);
  EXPECT_EQ(r.valid + r.offset + r.dilated, 0u);
  EXPECT_TRUE(all_zero(c));
  EXPECT_TRUE(r.valid_cloud);
  for (const ProbeRecord& p : r.probes) EXPECT_EQ(p.back_face_share, 1.0f);
}

// Probes exactly on surfaces: a grid whose bottom layer lies on the floor's top face (z = 0)
// and whose x = 0 plane lies on a wall's face. Finite SH, a valid cloud, and no probe is left
// with a capture from inside the geometry.
TEST(ProbeBake, ProbesExactlyOnSurfaces) {
  PENUMBRA_STABILITY("probes exactly on surfaces (a floor's top face, a wall's face)",
                     "finite SH, a valid cloud, kept captures have back-face share <= 0.25",
                     "validity offset");
  const BakeScene s = parse(R"({
    "geometry": [{"kind": "box", "center": [0,0,-0.5], "size": [20,20,1], "albedo": [0.5,0.5,0.5]},
                 {"kind": "box", "center": [-0.5,0,2], "size": [1,20,4], "albedo": [0.5,0.5,0.5]}],
    "lights": [{"center": [3,0,5], "radius": 0.5, "radiance": [50,50,50]}],
    "probes": {"min": [0,-2,0], "max": [4,2,3], "spacing": 1}})");
  BakeReport r;
  const data::ProbeCloud c = bake_probe_cloud(s, fast(), &r);
  EXPECT_TRUE(all_finite(c));
  EXPECT_TRUE(r.valid_cloud);
  EXPECT_EQ(r.probes.size(), 5u * 5u * 4u);
  for (const ProbeRecord& p : r.probes) {
    if (p.state == ProbeState::kValid || p.state == ProbeState::kOffset) {
      EXPECT_LE(p.back_face_share, 0.25f);
    }
  }
}

TEST(ProbeBake, NanInSceneRejectedNamingTheFile) {
  PENUMBRA_STABILITY("NaN in the scene file", "rejected, the message names the file", "-");
  try {
    parse_bake_scene(R"({"geometry": [{"kind": "sphere", "center": [0, NaN, 0], "radius": 1}],
                         "probes": {"min": [0,0,0], "max": [1,1,1], "spacing": 1}})",
                     "scenes/nan.json", kData);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("scenes/nan.json"), std::string::npos) << e.what();
  }
}

// Validity in the room: the x = 0 column of the grid lies inside the inner wall. Without
// validity those probes capture black; with it none is left inside a solid and none is black.
TEST(ProbeBake, RoomValidity) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  BakeSettings b = fast();
  b.validity = false;
  BakeReport before, after;
  bake_probe_cloud(s, b, &before);
  std::size_t inside = 0, black_inside = 0;
  for (const ProbeRecord& p : before.probes)
    if (s.inside(p.placed)) {
      ++inside;
      black_inside += p.dc == 0;
      EXPECT_GT(p.back_face_share, 0.25f);
    }
  EXPECT_EQ(inside, 26u);  // inner wall: x = 0, y = -3.5 .. 1.5, 4 heights; 2 in the ball
  EXPECT_EQ(black_inside, inside);
  b.validity = true;
  const data::ProbeCloud c = bake_probe_cloud(s, b, &after);
  EXPECT_EQ(after.offset + after.dilated, inside);
  EXPECT_EQ(after.black, 0u);
  // No probe is left inside a solid; the moved ones were captured with few back faces. (Their
  // light may be 0 on the wall's dark side at 64 samples: no bounce sample found a lit surface.)
  ASSERT_EQ(c.probe_count(), after.probes.size());  // input order kept, no merges here
  for (std::size_t i = 0; i < c.probe_count(); ++i) {
    const ProbeRecord& p = after.probes[i];
    EXPECT_FALSE(s.inside(p.position)) << i;
    EXPECT_EQ(c.positions[i], p.position);
    if (p.state == ProbeState::kOffset) {
      EXPECT_LE(p.back_face_share, 0.25f);
      EXPECT_LE(glm::length(p.position - p.placed), 0.6f);  // max offset 0.5 + clearance 0.1
    }
  }
}

TEST(ProbeBake, SameBytesForAnyThreadCountAndChunk) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  BakeSettings b = fast();
  std::vector<unsigned char> one, two;
  tbb::task_arena(1).execute(
      [&] { one = assets::encode_probe_cloud_file(bake_probe_cloud(s, b)); });
  b.chunk = 7;
  tbb::task_arena(2).execute(
      [&] { two = assets::encode_probe_cloud_file(bake_probe_cloud(s, b)); });
  EXPECT_EQ(one, two);
  b.seed = 2;
  EXPECT_NE(assets::encode_probe_cloud_file(bake_probe_cloud(s, b)), one);
}

TEST(ProbeBake, Bands) {
  PENUMBRA_STABILITY("2, 4 and 5 SH bands", "clouds of 2 and 4 bands; 5 rejected", "-");
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  for (int bands : {2, 4}) {
    BakeSettings b = fast();
    b.bands = bands;
    const data::ProbeCloud c = bake_probe_cloud(s, b);
    EXPECT_EQ(c.bands, bands);
    EXPECT_EQ(c.sh.size(), c.probe_count() * 3 * bands * bands);
  }
  BakeSettings b = fast();
  b.bands = 5;
  EXPECT_THROW(bake_probe_cloud(s, b), std::invalid_argument);
}

// Accuracy: relative RMS error of the interpolated irradiance against the reference
// integrator (direct + one bounce) at random free points of the room, six axis normals each,
// per grid spacing; and the leak metric at points within one spacing of the inner wall on its
// dark (+x) side, with and without validity. Prints the table of docs/probe_bake.md.
TEST(ProbeBakeAccuracy, RoomErrorVersusSpacing) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  const reference::Scene traced(s.desc);
  // The free-space points, and within one (1 m) spacing of the inner wall its dark side (+x,
  // away from the lamp) and its lit side (room_accuracy_points.h).
  const auto sets = accuracy::room_point_sets(s, traced);
  const auto error = [&](const data::ProbeCloud& cloud, accuracy::RoomSet set) {
    return accuracy::set_error(cloud, sets[set]);
  };
  // Validity off; on with one-sided virtual offsets; on with both sides (the default).
  std::printf(
      "spacing  probes  rel_rms: off   one-sided  both  | dark side: off  one-sided  both  | "
      "lit side: off  one-sided  both  | bake_s\n");
  double coarse = 0, fine = 0;
  for (float spacing : {2.0f, 1.0f, 0.5f}) {
    BakeSettings b;
    b.spacing = spacing;
    b.samples = 512;
    BakeReport r[3];
    data::ProbeCloud c[3];
    b.validity = false;
    c[0] = bake_probe_cloud(s, traced, b, &r[0]);
    b.validity = true;
    b.validity_settings.both_sides = false;
    c[1] = bake_probe_cloud(s, traced, b, &r[1]);
    b.validity_settings.both_sides = true;
    c[2] = bake_probe_cloud(s, traced, b, &r[2]);
    double e[3][3];
    for (int k = 0; k < 3; ++k) {
      e[0][k] = error(c[k], accuracy::kFree);
      e[1][k] = error(c[k], accuracy::kDarkSide);
      e[2][k] = error(c[k], accuracy::kLitSide);
      EXPECT_TRUE(r[k].valid_cloud);
    }
    std::printf(
        "%-7g  %6zu  %12.3f  %9.3f  %5.3f | %14.3f  %9.3f  %5.3f | %13.3f  %9.3f  %5.3f | %6.2f\n",
        double(spacing), c[2].probe_count(), e[0][0], e[0][1], e[0][2], e[1][0], e[1][1], e[1][2],
        e[2][0], e[2][1], e[2][2], r[2].total_seconds);
    if (spacing == 2.0f) coarse = e[0][2];
    if (spacing == 0.5f) fine = e[0][2];
  }
  EXPECT_LT(fine, coarse);  // more probes, less error
  EXPECT_LT(fine, 0.5);
}

}  // namespace
}  // namespace penumbra::probe_bake
