// probe_sky_bake.h: the main job's probe cloud baked per sky step and cached. A second bake with
// the same inputs reads every step from the cache (the same SH, no rays); a corrupt or foreign
// cache file is baked again and said so; another input gets another folder; the bounce brings
// the lit ground's light to a probe's underside, and turning the sky moves the light.
#include "penumbra/game/probe_sky_bake.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "common/stability.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

namespace penumbra::game {
namespace {

struct Fixture {
  data::HeightField field;
  data::EnvironmentMap map;
  data::ProbeCloud cloud;
  ProbeSkyBakeInputs in;
};

// A 17 x 17 field with a ridge along y, a sky with a bright patch near the horizon at +x
// (a low sun), and 8 probes 5-20 m above the ground.
std::unique_ptr<Fixture> make() {
  auto f = std::make_unique<Fixture>();
  f->field.width = f->field.height = 17;
  f->field.cell_size = 10.0f;
  for (int y = 0; y < 17; ++y)
    for (int x = 0; x < 17; ++x)
      f->field.heights.push_back(20.0f * std::exp(-0.05f * float((x - 8) * (x - 8))));
  f->map.width = 64;
  f->map.height = 32;
  f->map.rgb.assign(64 * 32 * 3, 0.2f);
  for (int y = 13; y < 15; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 3; ++c) f->map.rgb[3 * (y * 64 + x) + c] = 400.0f;
  std::vector<glm::vec3> pts;
  for (float z : {25.0f, 45.0f})
    for (float x : {30.0f, 130.0f})
      for (float y : {40.0f, 120.0f}) pts.emplace_back(x, y, z);
  f->cloud = probe_cloud::build_probe_cloud(pts, {}, {});
  f->in.field = &f->field;
  f->in.map = &f->map;
  f->in.steps = 4;
  f->in.samples = 64;
  return f;
}

std::filesystem::path temp_dir(const char* name) {
  const auto d = std::filesystem::temp_directory_path() /
                 (std::string("penumbra_probe_sky_") + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

TEST(ProbeSkyBake, SecondRunReadsTheCacheAndGetsTheSameSh) {
  const auto f = make();
  const auto dir = temp_dir("same");
  const ProbeSkySteps first = bake_probe_sky_steps(f->in, f->cloud, dir);
  EXPECT_EQ(first.baked, 4u);
  EXPECT_EQ(first.loaded, 0u);
  EXPECT_TRUE(first.notes.empty());
  const ProbeSkySteps again = bake_probe_sky_steps(f->in, f->cloud, dir);
  EXPECT_EQ(again.baked, 0u);
  EXPECT_EQ(again.loaded, 4u);
  EXPECT_EQ(again.folder, first.folder);
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(first.sh[k].size(), f->cloud.probe_count() * 27);
    EXPECT_EQ(again.sh[k], first.sh[k]) << k;
  }
  // Without a cache: the same numbers (deterministic), every step traced.
  const ProbeSkySteps none = bake_probe_sky_steps(f->in, f->cloud, {});
  EXPECT_EQ(none.baked, 4u);
  EXPECT_EQ(none.sh, first.sh);
  // Only the steps asked for.
  const int two[] = {2};
  const ProbeSkySteps one = bake_probe_sky_steps(f->in, f->cloud, {}, two);
  EXPECT_TRUE(one.sh[0].empty());
  EXPECT_EQ(one.sh[2], first.sh[2]);
  std::filesystem::remove_all(dir);
}

TEST(ProbeSkyBake, CorruptOrForeignFilesAreBakedAgainAndOtherInputsGetAnotherFolder) {
  PENUMBRA_STABILITY("a truncated or foreign cached sky step",
                     "baked again with a note naming the file", "-");
  const auto f = make();
  const auto dir = temp_dir("corrupt");
  const ProbeSkySteps first = bake_probe_sky_steps(f->in, f->cloud, dir);
  // Truncate step 1's file; write step 2's with another cloud's probes.
  const auto file1 = first.folder / "sky_001.pcld";
  std::filesystem::resize_file(file1, std::filesystem::file_size(file1) / 2);
  {
    std::vector<glm::vec3> other(f->cloud.positions);
    other[0].z += 1.0f;
    data::ProbeCloud c = probe_cloud::build_probe_cloud(other, {}, {});
    c.sh.assign(c.probe_count() * 27, 0.0f);
    assets::save_probe_cloud_file(first.folder / "sky_002.pcld", c);
  }
  const ProbeSkySteps again = bake_probe_sky_steps(f->in, f->cloud, dir);
  EXPECT_EQ(again.loaded, 2u);
  EXPECT_EQ(again.baked, 2u);
  ASSERT_EQ(again.notes.size(), 2u);
  EXPECT_NE(again.notes[0].find("sky_001.pcld"), std::string::npos) << again.notes[0];
  EXPECT_NE(again.notes[1].find("sky_002.pcld: holds other probes"), std::string::npos)
      << again.notes[1];
  EXPECT_EQ(again.sh, first.sh);
  // Rewritten: a third run loads everything.
  EXPECT_EQ(bake_probe_sky_steps(f->in, f->cloud, dir).loaded, 4u);
  ProbeSkyBakeInputs more = f->in;
  more.samples = 128;
  EXPECT_NE(probe_sky_bake_key(more, f->cloud.positions),
            probe_sky_bake_key(f->in, f->cloud.positions));
  const ProbeSkySteps other = bake_probe_sky_steps(more, f->cloud, dir);
  EXPECT_NE(other.folder, first.folder);
  EXPECT_EQ(other.baked, 4u);
  std::filesystem::remove_all(dir);
}

// The irradiance a probe's underside (normal -z) gets: 0 from the sky through the ground without
// the bounce, > 0 with it; and turning the sky by half a turn moves the low sun's light from the
// +x side to the -x side.
TEST(ProbeSkyBake, BounceLightsTheUndersideAndTheSkyTurns) {
  const auto f = make();
  const auto e = [&](const std::vector<float>& sh, std::size_t p, glm::vec3 n) {
    const sh::Coeffs<3> y = sh::eval_basis<3>(n);
    double s = 0;
    for (int k = 0; k < 9; ++k) s += sh[p * 27 + 9 + k] * y[k];  // green
    return s;
  };
  ProbeSkyBakeInputs flat = f->in;
  flat.bounce = false;
  const ProbeSkySteps direct = bake_probe_sky_steps(flat, f->cloud, {});
  const ProbeSkySteps bounced = bake_probe_sky_steps(f->in, f->cloud, {});
  const std::size_t low = 0;  // (30, 40, 25): west of the ridge, low
  EXPECT_GT(e(bounced.sh[0], low, {0, 0, -1}), e(direct.sh[0], low, {0, 0, -1}) + 0.05);
  // Step 0: the sun at +x; step 2 (half a turn): at -x.
  EXPECT_GT(e(direct.sh[0], low, {1, 0, 0}), 2 * e(direct.sh[0], low, {-1, 0, 0}));
  EXPECT_GT(e(direct.sh[2], low, {-1, 0, 0}), 2 * e(direct.sh[2], low, {1, 0, 0}));
}

// A static mesh (a roof over a probe) occludes the sky there and is part of the cache key; a
// probe away from it is unchanged.
TEST(ProbeSkyBake, StaticMeshesOccludeAndChangeTheKey) {
  const auto f = make();
  auto roof = std::make_shared<data::MeshData>();
  // A roof 10 m above the probe at (30, 40, 25), reaching 70 m past it towards the low sun (+x)
  // and at least 80 m the other ways, facing down and up (two triangles each).
  roof->positions = {{-70, -60, 35}, {100, -60, 35}, {100, 100, 35}, {-70, 100, 35}};
  roof->indices = {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2};
  ProbeSkyBakeInputs covered = f->in;
  covered.meshes.push_back({roof, glm::vec3(0.9f, 0.1f, 0.1f)});
  EXPECT_NE(probe_sky_bake_key(covered, f->cloud.positions),
            probe_sky_bake_key(f->in, f->cloud.positions));
  const ProbeSkySteps open = bake_probe_sky_steps(f->in, f->cloud, {});
  const ProbeSkySteps shut = bake_probe_sky_steps(covered, f->cloud, {});
  const auto up = [](const std::vector<float>& sh, std::size_t p) {  // green, facing up
    const sh::Coeffs<3> y = sh::eval_basis<3>(glm::vec3(0, 0, 1));
    double s = 0;
    for (int k = 0; k < 9; ++k) s += sh[p * 27 + 9 + k] * y[k];
    return s;
  };
  const std::size_t low = 0;  // (30, 40, 25): under the roof
  EXPECT_LT(up(shut.sh[0], low), 0.5 * up(open.sh[0], low));
  const std::size_t far = 3;  // (130, 120, 25): beyond its corner, the sun in view
  EXPECT_GT(up(shut.sh[0], far), 0.6 * up(open.sh[0], far));
}

TEST(ProbeSkyBake, BadInputsAreRejected) {
  PENUMBRA_STABILITY("no sky map, 0 sky steps, a step index out of range", "std::invalid_argument",
                     "-");
  const auto f = make();
  ProbeSkyBakeInputs in = f->in;
  in.map = nullptr;
  EXPECT_THROW(bake_probe_sky_steps(in, f->cloud, {}), std::invalid_argument);
  in = f->in;
  in.steps = 0;
  EXPECT_THROW(bake_probe_sky_steps(in, f->cloud, {}), std::invalid_argument);
  in = f->in;
  const int bad[] = {4};
  EXPECT_THROW(bake_probe_sky_steps(in, f->cloud, {}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::game
