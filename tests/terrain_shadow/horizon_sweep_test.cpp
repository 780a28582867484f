// The line sweep against the brute-force ray march: identical where lines pass through texels
// (azimuths along the axes and diagonals), within the between-line interpolation elsewhere.
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <tbb/task_arena.h>

#include "common/stability.h"
#include "penumbra/assets/procedural.h"
#include "sweep_lanes.h"  // internal: the kernels' two compiled copies
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

// fBm mountains with 1 m cells (steeper than test::mountains).
data::HeightField unit_cell_mountains(int n, std::uint64_t seed = 3) {
  return assets::procedural_scene("mountains", {n, static_cast<float>(n)}, seed);
}

// A field swept once through a workspace: where the edit tests start.
struct Swept {
  data::HeightField f;
  HorizonParams p;
  SweepWorkspace ws;
  HorizonGrid horizons;
};
Swept swept(int n, std::uint64_t seed, int azimuths) {
  Swept s{unit_cell_mountains(n, seed), {}, {}, {}};
  s.p.azimuths = azimuths;
  sweep_horizons(s.f, s.p, TexelRect::all(s.f), s.horizons, s.ws);
  return s;
}

void raise_box(data::HeightField& f, const TexelRect& b, float dh) {
  for (int y = b.y0; y < b.y1; ++y)
    for (int x = b.x0; x < b.x1; ++x) f.at(x, y) += dh;
}

// An edit of `box` through `ws` (sweep_horizons_through) against a full sweep, bit for bit.
::testing::AssertionResult edit_equals_full_sweep(const data::HeightField& f,
                                                  const HorizonParams& p, SweepWorkspace& ws,
                                                  HorizonGrid& edited, const TexelRect& box) {
  std::vector<unsigned char> changed;
  sweep_horizons_through(f, p, box, edited, changed, ws);
  HorizonGrid full;
  sweep_horizons(f, p, TexelRect::all(f), full);
  if (edited.angles == full.angles) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "box at " << box.x0 << ", " << box.y0;
}

float max_abs_difference(const HorizonGrid& a, const HorizonGrid& b) {
  float m = 0;
  for (std::size_t i = 0; i < a.angles.size(); ++i)
    m = std::max(m, std::abs(a.angles[i] - b.angles[i]));
  return m;
}

TEST(HorizonSweep, EqualsBruteForceWhereLinesPassThroughTexels) {
  const auto f = unit_cell_mountains(48);
  HorizonParams p;
  p.azimuths = 8;  // 0, 45, 90, ... degrees: every line passes through texel centres
  for (bool clamp : {true, false}) {
    p.clamp_at_zero = clamp;
    HorizonGrid sweep, brute;
    sweep_horizons(f, p, TexelRect::all(f), sweep);
    brute_force_horizons(f, p, TexelRect::all(f), brute);
    EXPECT_LE(max_abs_difference(sweep, brute), 1e-6f) << "clamp " << clamp;
  }
}

TEST(HorizonSweep, EqualsBruteForceOnTheSameSamplesForEveryAzimuth) {
  // The hull finds the steepest sample exactly: brute force over the same line samples agrees
  // to float precision at 37 azimuths (none along an axis), clamped or not.
  const auto f = unit_cell_mountains(48, 5);
  HorizonParams p;
  p.azimuths = 37;
  for (bool clamp : {true, false}) {
    p.clamp_at_zero = clamp;
    HorizonGrid sweep, brute;
    sweep_horizons(f, p, TexelRect::all(f), sweep);
    brute_force_horizons(f, p, TexelRect::all(f), brute, BruteForceSampling::kSweepLines);
    EXPECT_LE(max_abs_difference(sweep, brute), 2e-6f) << "clamp " << clamp;
  }
}

TEST(HorizonSweep, LaneKernelEqualsTheScalarKernel) {
  // Eight lines per AVX2 step against one line at a time, on a field whose size is not a
  // multiple of 8, over a region touching no border, clamped or not.
  const auto f = unit_cell_mountains(45, 7);
  HorizonParams p;
  p.azimuths = 23;
  const TexelRect r{3, 5, 40, 33};
  for (bool clamp : {true, false}) {
    p.clamp_at_zero = clamp;
    HorizonGrid lanes, scalar;
    sweep_horizons(f, p, r, lanes);
    sweep_horizons_scalar(f, p, r, scalar);
    EXPECT_LE(max_abs_difference(lanes, scalar), 1e-6f) << "clamp " << clamp;
  }
}

TEST(HorizonSweep, PlanesPassBlocksOfEverySizeEqualTheScalarKernel) {
  // The planes pass copies x-major azimuths in 16 x 16 blocks on AVX-512, two 8 x 8 blocks where
  // only 8 columns are left, and 8 x 8 blocks for the rows after the last 16: a region of 40 x 40
  // texels (40 = 2 x 16 + 8 both ways) and one of 24 x 56 take every kind.
  const auto f = unit_cell_mountains(64, 5);
  HorizonParams p;
  p.azimuths = 16;
  for (const TexelRect r : {TexelRect{3, 7, 43, 47}, TexelRect{20, 2, 44, 58}}) {
    HorizonGrid lanes, scalar;
    sweep_horizons(f, p, r, lanes);
    sweep_horizons_scalar(f, p, r, scalar);
    EXPECT_LE(max_abs_difference(lanes, scalar), 1e-6f) << r.x0 << "," << r.y0;
  }
}

TEST(HorizonSweep, LineInterpolationErrorAgainstEachTexelsOwnRay) {
  // What the sweep gives up for sharing lines: a texel's horizon is blended from the two lines
  // less than a cell either side of it. Measured on 48x48 mountains, 32 azimuths: mean 0.0049
  // rad, max 0.60 rad (a texel beside a sharp crest, where the two lines see different crests).
  const auto f = unit_cell_mountains(48);
  HorizonParams p;
  p.azimuths = 32;
  HorizonGrid sweep, brute;
  sweep_horizons(f, p, TexelRect::all(f), sweep);
  brute_force_horizons(f, p, TexelRect::all(f), brute);
  double sum = 0;
  for (std::size_t i = 0; i < sweep.angles.size(); ++i)
    sum += std::abs(sweep.angles[i] - brute.angles[i]);
  const double mean = sum / sweep.angles.size();
  EXPECT_LT(mean, 0.01);
  EXPECT_GT(mean, 1e-4);  // not secretly the same computation
  EXPECT_LT(max_abs_difference(sweep, brute), 0.8f);
}

TEST(HorizonSweep, ThroughAnEditEqualsAFullSweepAndFlagsWhatChanged) {
  data::HeightField f = unit_cell_mountains(50, 11);
  HorizonParams p;
  p.azimuths = 19;
  HorizonGrid before, updated, full;
  sweep_horizons(f, p, TexelRect::all(f), before);
  const TexelRect edit{20, 14, 29, 22};
  for (int y = edit.y0; y < edit.y1; ++y)
    for (int x = edit.x0; x < edit.x1; ++x) f.at(x, y) += 9.0f;  // a raised block
  updated = before;
  std::vector<unsigned char> changed;
  const std::size_t pairs = sweep_horizons_through(f, p, edit, updated, changed);
  sweep_horizons(f, p, TexelRect::all(f), full);
  EXPECT_LT(pairs, full.angles.size() / 2) << "only the lines through the edit";
  std::size_t flagged = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      bool differs = false;
      for (int k = 0; k < p.azimuths; ++k) {
        ASSERT_EQ(updated.texel(x, y)[k], full.texel(x, y)[k]) << x << "," << y << "," << k;
        differs = differs || before.texel(x, y)[k] != full.texel(x, y)[k];
      }
      ASSERT_EQ(changed[static_cast<std::size_t>(y) * f.width + x] != 0, differs) << x << "," << y;
      flagged += differs;
    }
  EXPECT_GT(flagged, 50u);
}

TEST(HorizonSweep, AReusedWorkspaceGivesWhatAFreshOneGives) {
  // One workspace through calls whose shapes differ (fields of two sizes, a region, an edit,
  // 40 azimuths: blocks of 8 and a last one of 8; the buffers keep what the last call left):
  // every call equals the same call on a fresh workspace, bit for bit.
  SweepWorkspace ws;
  HorizonParams p;
  p.azimuths = 40;
  auto same = [&](const data::HeightField& f, const TexelRect& r) {
    HorizonGrid reused, fresh;
    sweep_horizons(f, p, r, reused, ws);
    sweep_horizons(f, p, r, fresh);
    EXPECT_EQ(reused.angles, fresh.angles) << f.width << "x" << f.height << " " << r.x0;
    return reused;
  };
  data::HeightField a = unit_cell_mountains(50, 4);
  data::HeightField b =
      unit_cell_mountains(61, 9);  // cropped to 37 x 23: x- and y-major rows differ
  b.width = 37, b.height = 23;
  b.heights.resize(37 * 23);
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 37; ++x) b.at(x, y) = a.at(x, y) + 0.5f * y;
  same(a, TexelRect::all(a));
  same(b, TexelRect::all(b));
  same(a, TexelRect{7, 3, 45, 29});
  HorizonGrid edited = same(a, TexelRect::all(a)), expected = edited;
  for (int y = 10; y < 14; ++y)
    for (int x = 30; x < 33; ++x) a.at(x, y) -= 6.0f;
  std::vector<unsigned char> c1, c2;
  sweep_horizons_through(a, p, TexelRect{30, 10, 33, 14}, edited, c1, ws);
  sweep_horizons_through(a, p, TexelRect{30, 10, 33, 14}, expected, c2);
  EXPECT_EQ(edited.angles, expected.angles);
  EXPECT_EQ(c1, c2);
  same(a, TexelRect::all(a));  // after an edit, whose accumulators are not left zeroed
  SweepWorkspace copied = ws, moved = std::move(ws);  // a copy starts empty; a moved-from one
  HorizonGrid c, m, w;                                // makes new buffers
  sweep_horizons(b, p, TexelRect::all(b), c, copied);
  sweep_horizons(b, p, TexelRect::all(b), m, moved);
  sweep_horizons(b, p, TexelRect::all(b), w, ws);  // NOLINT(bugprone-use-after-move)
  EXPECT_EQ(c.angles, m.angles);
  EXPECT_EQ(c.angles, w.angles);
}

TEST(HorizonSweep, WallCastsItsExactAngle) {
  data::HeightField f;
  f.width = f.height = 32;
  f.cell_size = 2;
  f.heights.assign(32 * 32, 0.0f);
  for (int y = 0; y < 32; ++y) f.at(20, y) = 10;  // a wall 10 m high at x = 20
  HorizonParams p;
  p.azimuths = 4;
  HorizonGrid g;
  sweep_horizons(f, p, TexelRect::all(f), g);
  // From x = 10 looking +x: wall 10 cells = 20 m away, 10 m high.
  EXPECT_NEAR(g.texel(10, 16)[0], std::atan(10.0f / 20.0f), 1e-6f);
  EXPECT_NEAR(g.texel(10, 16)[2], 0.0f, 1e-6f);  // looking -x: flat
  EXPECT_NEAR(g.texel(25, 16)[0], 0.0f, 1e-6f);  // past the wall
  // Unclamped, the wall top looks down on the flat ground behind it.
  p.clamp_at_zero = false;
  sweep_horizons(f, p, TexelRect::all(f), g);
  EXPECT_NEAR(g.texel(20, 16)[0], std::atan(-10.0f / 22.0f), 1e-6f);  // farthest ground
  EXPECT_NEAR(g.texel(31, 16)[0], -kPi / 2, 1e-6f);                   // nothing ahead at the border
  // Height scale multiplies heights.
  p.clamp_at_zero = true;
  p.height_scale = 0.5f;
  sweep_horizons(f, p, TexelRect::all(f), g);
  EXPECT_NEAR(g.texel(10, 16)[0], std::atan(5.0f / 20.0f), 1e-6f);
}

// One direction (a key light's azimuth): at azimuth k it equals the full sweep's plane k; at
// any other angle, the exact angle of a wall seen along it.
TEST(HorizonSweep, OneDirectionEqualsTheSweepAndSeesAWall) {
  const data::HeightField f = unit_cell_mountains(48);
  HorizonParams p;
  p.azimuths = 16;
  HorizonGrid g;
  sweep_horizons_scalar(f, p, TexelRect::all(f), g);
  std::vector<float> one;
  for (int k : {0, 3, 9}) {
    sweep_direction_horizons(f, p, 2 * kPi * k / 16, TexelRect::all(f), one);
    ASSERT_EQ(one.size(), 48u * 48u);
    float m = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x)
        m = std::max(m, std::abs(one[static_cast<std::size_t>(y) * 48 + x] - g.texel(x, y)[k]));
    EXPECT_LT(m, 1e-6f) << k;
  }
  data::HeightField w;
  w.width = w.height = 32;
  w.cell_size = 2;
  w.heights.assign(32 * 32, 0.0f);
  for (int y = 0; y < 32; ++y) w.at(20, y) = 10;  // a wall 10 m high at x = 20
  const float phi = 0.3f;  // towards +x, turned: the wall is 20 m / cos(phi) away along it
  sweep_direction_horizons(w, p, phi, TexelRect::all(w), one);
  EXPECT_NEAR(one[16 * 32 + 10], std::atan(10.0f * std::cos(phi) / 20.0f), 2e-3f);
  EXPECT_NEAR(one[16 * 32 + 25], 0.0f, 1e-6f);  // past the wall
  EXPECT_THROW(sweep_direction_horizons(w, p, std::nan(""), TexelRect::all(w), one),
               std::invalid_argument);
}

TEST(HorizonSweep, RegionUpdateEqualsFullUpdateInsideIt) {
  const auto f = unit_cell_mountains(40);
  HorizonParams p;
  p.azimuths = 16;
  HorizonGrid full, part;
  sweep_horizons(f, p, TexelRect::all(f), full);
  const TexelRect r{5, 12, 21, 30};
  sweep_horizons(f, p, r, part);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int k = 0; k < p.azimuths; ++k) {
        if (r.contains(x, y))
          ASSERT_EQ(part.texel(x, y)[k], full.texel(x, y)[k]) << x << "," << y << "," << k;
        else
          ASSERT_EQ(part.texel(x, y)[k], 0.0f);
      }
}

TEST(HorizonSweep, ThinRegionsEqualTheFullSweepInsideThem) {
  // The records pass splits each block of azimuths into bands of rows, at least eight tasks
  // (horizon_sweep.cpp): regions with fewer rows than that (one band a row) and of one column
  // still take every texel's record from its own row of the planes.
  const auto f = unit_cell_mountains(40, 3);
  HorizonParams p;
  p.azimuths = 16;  // two blocks of 8: four bands a block where the region has the rows
  HorizonGrid full;
  sweep_horizons(f, p, TexelRect::all(f), full);
  for (const TexelRect r : {TexelRect{4, 9, 36, 10}, TexelRect{2, 20, 31, 23},
                            TexelRect{6, 30, 39, 35}, TexelRect{17, 1, 18, 38}}) {
    HorizonGrid part;
    sweep_horizons(f, p, r, part);
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x)
        for (int k = 0; k < p.azimuths; ++k)
          ASSERT_EQ(part.texel(x, y)[k], r.contains(x, y) ? full.texel(x, y)[k] : 0.0f)
              << r.x0 << "," << r.y0 << " " << x << "," << y << "," << k;
  }
}

TEST(HorizonSweep, LargeFieldsWholeLineRecordsEqualQuarterRegions) {
  // From 256^2 texels, with 32 azimuths on 2 threads, tasks take 16 azimuths and write each
  // texel's record lines whole with streaming stores; regions of a quarter of that take 8 and
  // write them in halves. Same horizons, bit for bit.
  const auto f = unit_cell_mountains(264, 21);
  HorizonParams p;
  p.azimuths = 32;
  HorizonGrid full, quarters;
  tbb::task_arena two(2);
  two.execute([&] {
    sweep_horizons(f, p, TexelRect::all(f), full);
    for (const TexelRect& r : {TexelRect{0, 0, 132, 132}, TexelRect{132, 0, 264, 132},
                               TexelRect{0, 132, 132, 264}, TexelRect{132, 132, 264, 264}})
      sweep_horizons(f, p, r, quarters);
  });
  EXPECT_EQ(full.angles, quarters.angles);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(full.angles.data()) % 64, 0u);
}

TEST(HorizonSweep, TheThreadCountChangesNoBit) {
  // Every azimuth is a task of its own and the records are written per block and band of rows
  // after them (horizon_sweep.cpp): on 1, 2 and 3 threads (blocks of 16 azimuths, then of 8, since
  // 32 / 16 < 3), through one workspace, the same horizons bit for bit.
  const auto f = unit_cell_mountains(264, 21);
  HorizonParams p;
  p.azimuths = 32;
  SweepWorkspace ws;
  std::vector<HorizonGrid> grids(3);
  for (int threads = 1; threads <= 3; ++threads)
    tbb::task_arena(threads).execute(
        [&] { sweep_horizons(f, p, TexelRect::all(f), grids[threads - 1], ws); });
  EXPECT_EQ(grids[0].angles, grids[1].angles);
  EXPECT_EQ(grids[0].angles, grids[2].angles);
}

TEST(HorizonSweep, PlanesKeptWhereTheirThreadsWroteThemChangeNoBit) {
  // Each azimuth goes into a plane slot that the sweeping thread wrote in the last sweep, so
  // which slot holds which azimuth changes with the threads and the scheduler, and the records
  // read each azimuth from its slot (horizon_sweep.cpp, PlaneSlots). One workspace through
  // sweeps on 3, 2, 1, 2, 3 and 2 threads (32 azimuths: blocks of 8 on 3 threads, of 16 on
  // fewer; 20 azimuths: a last block of 4), each equal to a fresh one-thread sweep bit for bit.
  const auto f = unit_cell_mountains(264, 23);
  for (int azimuths : {32, 20}) {
    HorizonParams p;
    p.azimuths = azimuths;
    HorizonGrid expected;
    tbb::task_arena(1).execute([&] { sweep_horizons(f, p, TexelRect::all(f), expected); });
    SweepWorkspace ws;
    for (int threads : {3, 2, 1, 2, 3, 2}) {
      HorizonGrid grid;
      tbb::task_arena(threads).execute([&] { sweep_horizons(f, p, TexelRect::all(f), grid, ws); });
      ASSERT_EQ(grid.angles, expected.angles) << azimuths << " azimuths, " << threads << " threads";
    }
  }
}

TEST(HorizonSweep, EditsInTurnResumeFromKeptHullsBitForBit) {
  // One workspace through a run of edits: the same box again, moved along x and y both ways,
  // far away, back. Each edit's line groups resume from the hulls the edits before left where
  // those lie at or ahead of it (sweep_lanes.h, GroupHull), and walk from the far end where
  // not; every result equals a full sweep of the edited field, bit for bit.
  auto [f, p, ws, edited] = swept(64, 21, 24);
  const TexelRect boxes[] = {{28, 30, 36, 37}, {28, 30, 36, 37}, {31, 30, 39, 37},
                             {25, 27, 33, 34}, {28, 33, 36, 40}, {5, 50, 12, 58},
                             {28, 30, 36, 37}, {29, 31, 34, 35}, {0, 0, 6, 4}};
  float sign = 1;
  for (const TexelRect& b : boxes) {
    for (int y = b.y0; y < b.y1; ++y)
      for (int x = b.x0; x < b.x1; ++x) f.at(x, y) += sign * (3.0f + 0.25f * (x + y));
    sign = -sign;
    ASSERT_TRUE(edit_equals_full_sweep(f, p, ws, edited, b));
  }
}

TEST(HorizonSweep, ASoleWritersEditsOfOneRectangleEqualAPlainWorkspacesAndAFullSweep) {
  // With SweepWorkspace::set_sole_writer an edit keeps the values it recomputed along each
  // azimuth's lines, and the next edit of the same rectangle compares with those instead of the
  // grid's records. One box edited in turn (raised, lowered, left as it was), another box
  // between, then the first again, a big box twice (its lines cover more than an eighth of the
  // field: no values kept), the first again: each result and its changed flags equal those of a
  // workspace without the setting, and the horizons equal a full sweep, bit for bit.
  auto [f, p, ws, edited] = swept(128, 21, 24);
  ws.set_sole_writer(true);
  SweepWorkspace plain_ws;
  HorizonGrid plain = edited;
  const TexelRect b{60, 62, 68, 69}, c{62, 65, 66, 67}, big{16, 20, 112, 100};
  const std::pair<TexelRect, float> steps[] = {{b, 4.0f},    {b, -6.0f}, {b, 0.0f},  {b, 2.5f},
                                               {c, -3.0f},   {b, 1.0f},  {b, -1.0f}, {big, 2.0f},
                                               {big, -1.0f}, {b, 0.5f}};
  int changed_texels = 0;
  for (const auto& [box, dh] : steps) {
    raise_box(f, box, dh);
    std::vector<unsigned char> kept_flags, plain_flags;
    sweep_horizons_through(f, p, box, plain, plain_flags, plain_ws);
    ASSERT_TRUE(edit_equals_full_sweep(f, p, ws, edited, box)) << "dh " << dh;
    kept_flags.clear();
    sweep_horizons_through(f, p, box, edited, kept_flags, ws);  // again: nothing changes
    ASSERT_EQ(std::count(kept_flags.begin(), kept_flags.end(), 1), 0) << "dh " << dh;
    ASSERT_EQ(edited.angles, plain.angles) << "dh " << dh;
    changed_texels += static_cast<int>(std::count(plain_flags.begin(), plain_flags.end(), 1));
  }
  EXPECT_GT(changed_texels, 500);
}

TEST(HorizonSweep, AGridResetBetweenEditsStaysExactUnlessTheWorkspaceIsTheSoleWriter) {
  // Without the setting an edit compares with the grid's records, so a grid copy-assigned back
  // to its state before an edit (the same buffer) and edited again is exact; a workspace
  // assigned over drops the values its edits kept, so a sole writer's owner that is assigned
  // (grid and workspace together, as TerrainShadowing's members) stays exact too.
  for (const bool sole : {false, true}) {
    auto [f, p, ws, edited] = swept(128, 5, 16);
    ws.set_sole_writer(sole);
    const HorizonGrid before = edited;
    const TexelRect b{60, 60, 66, 65};  // a brush's box: its lines cover under an eighth
    raise_box(f, b, 5.0f);
    std::vector<unsigned char> changed;
    sweep_horizons_through(f, p, b, edited, changed, ws);
    edited = before;
    if (sole) {
      SweepWorkspace other;
      other.set_sole_writer(true);
      ws = other;
    }
    ASSERT_TRUE(edit_equals_full_sweep(f, p, ws, edited, b)) << "sole writer " << sole;
  }
}

TEST(HorizonSweep, EditsAtTheBordersAndOfOneTexelEqualAFullSweep) {
  // The lines an edit recomputes are those whose samples read its rows at its columns, and the
  // texels either side of them: edits on the field's corners and edges, one texel wide, and a
  // box the width of the field, over 37 azimuths (slopes of every size), bit for bit.
  auto [f, p, ws, edited] = swept(41, 17, 37);
  const TexelRect boxes[] = {{0, 0, 3, 2},   {38, 0, 41, 1},   {0, 39, 1, 41},  {40, 40, 41, 41},
                             {20, 0, 21, 1}, {17, 23, 18, 24}, {0, 18, 41, 20}, {9, 5, 10, 36}};
  float dh = 6.0f;
  for (const TexelRect& b : boxes) {
    raise_box(f, b, dh);
    dh = -dh * 0.8f;
    ASSERT_TRUE(edit_equals_full_sweep(f, p, ws, edited, b));
  }
}

TEST(HorizonSweep, AKeptHullIsTheHullAWalkFromTheFarEndTakes) {
  // The kernel itself, per azimuth (x- and y-major, both directions): an edit resumed from a
  // kept hull leaves the same hull at its first recorded column, and the same horizons, as the
  // same edit walked from the far end; the second box lies behind the first along +x and +y,
  // so most groups resume and walk the gap between the two.
  data::HeightField f = unit_cell_mountains(60, 5);
  HorizonParams p;
  p.azimuths = 16;
  HorizonGrid before;
  sweep_horizons(f, p, TexelRect::all(f), before);
  const TexelRect first{30, 28, 37, 34}, second{22, 20, 29, 26};
  for (int k = 0; k < p.azimuths; ++k) {
    data::HeightField g = f;
    raise_box(g, first, -5.0f);
    detail::LaneFields fields(g);
    detail::LaneScratch sc;
    std::vector<detail::GroupHull> kept;
    HorizonGrid out = before;
    std::vector<unsigned char> changed(g.heights.size(), 0);
    detail::sweep_azimuth_lines_through(g, fields, p, first, k, sc, out, changed.data(), &kept);
    raise_box(g, second, 4.0f);
    fields.assign(g);
    HorizonGrid walked = out;
    std::vector<detail::GroupHull> fresh;
    detail::sweep_azimuth_lines_through(g, fields, p, second, k, sc, out, changed.data(), &kept);
    detail::sweep_azimuth_lines_through(g, fields, p, second, k, sc, walked, changed.data(),
                                        &fresh);
    EXPECT_EQ(out.angles, walked.angles) << "azimuth " << k;
    for (const detail::GroupHull& w : fresh) {
      auto it = std::find_if(kept.begin(), kept.end(),
                             [&](const detail::GroupHull& h) { return h.cg == w.cg; });
      ASSERT_NE(it, kept.end()) << "azimuth " << k << ", group " << w.cg;
      EXPECT_TRUE(it->valid && w.valid);
      EXPECT_EQ(it->u, w.u);
      EXPECT_TRUE(std::equal(std::begin(w.size), std::end(w.size), std::begin(it->size)));
      EXPECT_EQ(it->h, w.h) << "azimuth " << k << ", group " << w.cg;
      EXPECT_EQ(it->j, w.j) << "azimuth " << k << ", group " << w.cg;
    }
  }
}

TEST(HorizonSweep, HullsKeptForAnotherFieldOrScaleAreNotUsed) {
  // The kept hulls hold only for the field they were taken on outside the edit: a field that
  // also differs elsewhere (a caller breaking the contract: here a tall block ahead of the edit
  // along +x), or another height scale, clears them, so the lines through the edit come out as
  // with a fresh workspace, bit for bit.
  auto [f, p, ws, out] = swept(56, 8, 16);
  const TexelRect box{20, 24, 27, 30};
  std::vector<unsigned char> changed;
  raise_box(f, box, 2.0f);
  sweep_horizons_through(f, p, box, out, changed, ws);  // hulls kept at the box
  raise_box(f, box, -1.0f);
  raise_box(f, {44, box.y0 - 2, 47, box.y1 + 2}, 40.0f);  // outside the box, ahead of it
  HorizonGrid reused = out, fresh = out;
  sweep_horizons_through(f, p, box, reused, changed, ws);
  sweep_horizons_through(f, p, box, fresh, changed);
  EXPECT_EQ(reused.angles, fresh.angles) << "another field";
  EXPECT_NE(reused.angles, out.angles);
  p.height_scale = 1.5f;
  raise_box(f, box, 1.0f);
  HorizonGrid scaled_reused = out, scaled_fresh = out;
  sweep_horizons_through(f, p, box, scaled_reused, changed, ws);
  sweep_horizons_through(f, p, box, scaled_fresh, changed);
  EXPECT_EQ(scaled_reused.angles, scaled_fresh.angles) << "another height scale";
}

TEST(HorizonSweep, TheAvx512KernelsGiveTheAvx2KernelsBits) {
  // The two compiled copies of the lane kernels (sweep_lanes.h; the AVX-512 one walks sixteen
  // lanes in one vector): a whole sweep, a region, one direction, and two edits through one
  // workspace (the second resumes from the hulls the first kept), bit for bit.
  if (detail::sweep_isa() != detail::SweepIsa::kAvx512)
    GTEST_SKIP() << "this CPU has no AVX-512: only the AVX2 kernels can run";
  data::HeightField f = unit_cell_mountains(70, 13);
  HorizonParams p;
  p.azimuths = 24;
  auto run = [&](detail::SweepIsa isa) {
    detail::force_sweep_isa(isa);
    HorizonGrid all, region;
    std::vector<float> one;
    SweepWorkspace ws;
    sweep_horizons(f, p, TexelRect::all(f), all, ws);
    sweep_horizons(f, p, TexelRect{9, 4, 61, 40}, region);
    sweep_direction_horizons(f, p, 0.7, TexelRect::all(f), one);
    data::HeightField g = f;
    const TexelRect box{40, 30, 44, 36};
    raise_box(g, box, 7.0f);
    HorizonGrid edited = all;
    std::vector<unsigned char> changed;
    sweep_horizons_through(g, p, box, edited, changed, ws);
    raise_box(g, box, -3.0f);
    sweep_horizons_through(g, p, box, edited, changed, ws);
    detail::force_sweep_isa(std::nullopt);
    return std::make_tuple(all.angles, region.angles, one, edited.angles, changed);
  };
  EXPECT_TRUE(run(detail::SweepIsa::kAvx2) == run(detail::SweepIsa::kAvx512));
}

// Samples of `fields` that differ from `f` (both copies) and non-zero padding samples.
std::pair<int, int> lane_fields_mismatch(const detail::LaneFields& fields,
                                         const data::HeightField& f) {
  constexpr int pad = detail::kGroupLines;
  const int w = f.width, h = f.height;
  int wrong = 0, padding = 0;
  auto same = [](float a, float b) {
    return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
  };
  // Copy `c`: `majors` runs of `stride` floats, sample (major, minor) at kGroupLines + minor.
  auto scan = [&](const std::vector<float>& c, int stride, int majors, int minors, auto sample) {
    for (int m = 0; m < majors; ++m)
      for (int i = 0; i < stride; ++i) {
        const float v = c[static_cast<std::size_t>(m) * stride + i];
        if (i - pad >= 0 && i - pad < minors)
          wrong += !same(v, sample(m, i - pad));
        else
          padding += v != 0.0f;
      }
  };
  scan(fields.x_major, fields.stride_x, w, h, [&](int x, int y) { return f.at(x, y); });
  scan(fields.y_major, fields.stride_y, h, w, [&](int y, int x) { return f.at(x, y); });
  return {wrong, padding};
}

TEST(HorizonSweep, TheLaneFieldsHoldEverySampleOnBothAxesAndZerosAround) {
  // LaneFields::assign against the field itself: both padded copies (x_major, y_major), for
  // sides that are not multiples of 8 (the 8 x 8 transposes' tails) and for a field of 512^2
  // texels or more (copied in parallel bands); update() then finds nothing changed. Assigned
  // again a field of the same shape, the copies skip the bands of 8 rows they hold already:
  // changes in a band's last row, in the short last band and to a sign bit (-0 for 0) must
  // still reach both copies.
  for (const auto& [w, h] : {std::pair{45, 37}, std::pair{520, 515}}) {
    data::HeightField f = unit_cell_mountains(std::max(w, h), 17);
    f = data::crop(f, 0, 0, w, h);
    detail::LaneFields fields;
    fields.x_major.assign(1, 0.0f);  // another shape: assign() sizes and zeroes its storage
    fields.assign(f);
    ASSERT_EQ(fields.x_major.size(), static_cast<std::size_t>(fields.stride_x) * w);
    ASSERT_EQ(fields.y_major.size(), static_cast<std::size_t>(fields.stride_y) * h);
    EXPECT_EQ(lane_fields_mismatch(fields, f), std::make_pair(0, 0)) << w << " x " << h;
    EXPECT_TRUE(fields.update(f).empty()) << w << " x " << h;

    data::HeightField g = f;
    g.at(w - 1, 15) += 1.0f;  // the last row of the band of rows 8-15
    g.at(3, h - 1) -= 2.0f;   // the last (short) band
    g.at(5, 20) = 0.0f;
    fields.assign(g);
    EXPECT_EQ(lane_fields_mismatch(fields, g), std::make_pair(0, 0)) << w << " x " << h;
    g.at(5, 20) = -0.0f;  // equal as a value, not as bits
    fields.assign(g);
    EXPECT_EQ(lane_fields_mismatch(fields, g), std::make_pair(0, 0)) << w << " x " << h;
    fields.assign(f);
    EXPECT_EQ(lane_fields_mismatch(fields, f), std::make_pair(0, 0)) << w << " x " << h;
  }
}

TEST(HorizonSweep, FlatSpikeAndExtremeSlopesStayFinite) {
  PENUMBRA_STABILITY("a single-texel spike of 1e6 (extreme slope)",
                     "horizon angles finite, within [0, pi/2]", "-");
  data::HeightField f;
  f.width = f.height = 16;
  f.heights.assign(256, 0.0f);
  f.at(8, 8) = 1e6f;  // single-texel spike, extreme slope
  HorizonParams p;
  p.azimuths = 16;
  HorizonGrid g;
  sweep_horizons(f, p, TexelRect::all(f), g);
  for (float a : g.angles) {
    ASSERT_TRUE(std::isfinite(a));
    ASSERT_GE(a, 0.0f);
    ASSERT_LE(a, kPi / 2);
  }
  EXPECT_GT(g.texel(7, 8)[0], 1.5f);  // the spike right next door is almost at the zenith
}

TEST(HorizonSweep, RejectsADistanceLimit) {
  PENUMBRA_STABILITY("a distance limit given to the (unlimited) sweep", "std::invalid_argument",
                     "use the march for limited distances");
  const auto f = unit_cell_mountains(8);
  HorizonParams p;
  p.limit_to_point = glm::vec2(1, 1);
  HorizonGrid g;
  EXPECT_THROW(sweep_horizons(f, p, TexelRect::all(f), g), std::invalid_argument);
}

TEST(HorizonBruteForce, DistanceLimitIgnoresOccludersBeyondTheLight) {
  data::HeightField f;
  f.width = f.height = 32;
  f.heights.assign(32 * 32, 0.0f);
  for (int y = 0; y < 32; ++y) f.at(20, y) = 10;
  HorizonParams p;
  p.azimuths = 4;
  p.clamp_at_zero = false;
  p.limit_to_point = glm::vec2(15, 16);  // light 5 m from texel (10, 16), before the wall
  HorizonGrid g;
  brute_force_horizons(f, p, {10, 16, 11, 17}, g);
  EXPECT_NEAR(g.texel(10, 16)[0], 0.0f, 1e-6f);  // flat ground up to the light
  p.limit_to_point = glm::vec2(25, 16);          // light behind the wall
  brute_force_horizons(f, p, {10, 16, 11, 17}, g);
  EXPECT_NEAR(g.texel(10, 16)[0], std::atan(10.0f / 10.0f), 1e-6f);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
