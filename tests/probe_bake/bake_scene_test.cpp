// Bake scene loader (bake_scene.h): the committed scenes load; bad input fails naming the file
// and the field; solids' inside tests; grid placement; dilation.
#include "penumbra/systems/probe_bake/bake_scene.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/systems/probe_bake/probe_placement.h"
#include "penumbra/systems/probe_bake/probe_validity.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

std::string error_of(const std::string& json) {
  try {
    parse_bake_scene(json, "scenes/bad.json", kData);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(BakeScene, CommittedScenesLoad) {
  const BakeScene room = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  EXPECT_EQ(room.name, "room");
  EXPECT_EQ(room.desc.meshes.size(), 7u);
  EXPECT_EQ(room.desc.spheres.size(), 1u);
  EXPECT_EQ(room.desc.lights.size(), 1u);
  EXPECT_FALSE(room.desc.environment);
  EXPECT_TRUE(room.inside({0, 0, 2}));            // inner wall
  EXPECT_FALSE(room.inside({1, 0, 2}));           // free
  EXPECT_TRUE(room.inside({0, 0, -0.1f}));        // floor
  EXPECT_TRUE(room.inside({-2.5f, 1.5f, 0.8f}));  // ball
  EXPECT_FALSE(room.inside({0, 3, 2}));           // the doorway
  if (!std::filesystem::exists(kData / "terrain")) GTEST_SKIP() << "no shared data";
  const BakeScene valley = load_bake_scene(kRoot / "scenes" / "valley.json", kData);
  EXPECT_EQ(valley.desc.height_fields.size(), 1u);
  EXPECT_EQ(valley.desc.meshes.size(), 5u);  // 2 walls + arch (3 boxes)
  EXPECT_TRUE(valley.desc.environment);
  EXPECT_TRUE(valley.inside({90, 90, -50}));   // under the ground
  EXPECT_FALSE(valley.inside({90, 90, 60}));   // above everything
  EXPECT_TRUE(valley.inside({80, 130, 35}));   // in the arch's lintel
  EXPECT_TRUE(valley.inside({41, 130, 35}));   // in its left pillar
  EXPECT_FALSE(valley.inside({80, 110, 37}));  // beside the lintel
}

TEST(BakeScene, ErrorsNameFileAndField) {
  PENUMBRA_STABILITY(
      "scene files with invalid JSON (NaN, 1e999), non-finite numbers, missing or unknown fields, "
      "wrong types, bad radius or albedo",
      "an error naming the file and the field", "-");
  const std::string probes = R"("probes": {"min": [0,0,0], "max": [1,1,1], "spacing": 1})";
  struct Case {
    std::string json, expect;
  } cases[] = {
      {"{" + probes + R"(, "geometry": [{"kind": "box", "center": [0,0,NaN], "size": [1,1,1]}]})",
       "scenes/bad.json: not valid JSON"},
      {"{" + probes + R"(, "geometry": [{"kind": "box", "center": [0,0,1e999], "size": [1,1,1]}]})",
       "scenes/bad.json: not valid JSON"},
      {"{" + probes + R"(, "geometry": [{"kind": "box", "center": [0,0,1e300], "size": [1,1,1]}]})",
       "scenes/bad.json: geometry[0].center[2]: not finite"},
      {"{" + probes + R"(, "geometry": [{"kind": "box", "center": [0,0,0]}]})",
       "scenes/bad.json: geometry[0].size: missing"},
      {"{" + probes + R"(, "geometry": [{"kind": "box", "center": [0,0,0], "size": [1,"a",1]}]})",
       "scenes/bad.json: geometry[0].size[1]: expected a number, got string"},
      {"{" + probes + R"(, "geometry": [{"kind": "cone"}]})",
       "scenes/bad.json: geometry[0].kind: unknown geometry kind \"cone\""},
      {"{" + probes + R"(, "geometry": [{"kind": "box", "centre": [0,0,0], "size": [1,1,1]}]})",
       "scenes/bad.json: geometry[0].centre: unknown field"},
      {R"({"probes": {"min": [0,0,0], "max": [1,1,1]}})",
       "scenes/bad.json: probes.spacing: missing"},
      {"{" + probes + R"(, "lights": [{"center": [0,0,0], "radius": -1, "radiance": [1,1,1]}]})",
       "scenes/bad.json: lights[0].radius: must be > 0"},
      {"{" + probes +
           R"(, "geometry": [{"kind": "box", "center": [0,0,0], "size": [1,1,1], "albedo": [2,0,0]}]})",
       "scenes/bad.json: geometry[0].albedo: each channel must be in [0, 1]"},
      {"{" + probes +
           R"(, "geometry": [{"kind": "gltf", "file": "models/none.glb", "translation": [0,0,0]}]})",
       "none.glb"},
      {"[]", "scenes/bad.json: (top): expected an object"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.json);
    EXPECT_NE(e.find(c.expect), std::string::npos) << "got: " << e << "\nexpected: " << c.expect;
  }
}

TEST(Placement, GridIsCentredAndCounted) {
  const auto p = grid_points({{0, 0, 0}, {2.5f, 1, 0}, 1.0f});
  ASSERT_EQ(p.size(), 3u * 2u * 1u);
  EXPECT_FLOAT_EQ(p[0].x, 0.25f);
  EXPECT_FLOAT_EQ(p[2].x, 2.25f);
  EXPECT_FLOAT_EQ(p[3].y, 1.0f);
  EXPECT_THROW(grid_points({{0, 0, 0}, {1, 1, 1}, 0.0f}), std::invalid_argument);
  EXPECT_THROW(grid_points({{0, 0, 0}, {1000, 1000, 1000}, 0.01f}), std::invalid_argument);
}

TEST(Validity, DilationWeightsByInverseSquaredDistance) {
  // Probe 1 invalid between a valid probe 1 m away (value 1) and one 2 m away (value 6): the
  // weights 1 and 1/4 give (1 + 6/4) / 1.25 = 2. Probe 3 is 10 m from everything: black.
  const std::vector<glm::vec3> pos = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {20, 0, 0}};
  std::vector<ProbeState> st = {ProbeState::kValid, ProbeState::kBlack, ProbeState::kValid,
                                ProbeState::kBlack};
  std::vector<float> sh = {1, 99, 6, 99};
  EXPECT_EQ(dilate(pos, st, sh, 1, 2.5f, 4), 1u);
  EXPECT_FLOAT_EQ(sh[1], 2.0f);
  EXPECT_EQ(st[1], ProbeState::kDilated);
  EXPECT_EQ(sh[3], 0.0f);
  EXPECT_EQ(st[3], ProbeState::kBlack);
  // A chain: each pass reaches one radius further.
  const std::vector<glm::vec3> chain = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  std::vector<ProbeState> cs = {ProbeState::kValid, ProbeState::kBlack, ProbeState::kBlack,
                                ProbeState::kBlack};
  std::vector<float> cv = {5, 0, 0, 0};
  EXPECT_EQ(dilate(chain, cs, cv, 1, 1.1f, 2), 1u);
  EXPECT_FLOAT_EQ(cv[1], 5.0f);
  EXPECT_FLOAT_EQ(cv[2], 5.0f);
  EXPECT_EQ(cs[3], ProbeState::kBlack);
}

}  // namespace
}  // namespace penumbra::probe_bake
