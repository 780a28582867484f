// The radial sweep's group kernel on AVX2 lanes against its scalar form (radial_sweep_lanes.h):
// the same floats, NaN where a line is outside its columns; and its AVX-512 copy (mask
// registers, a fourth hull point, paired links) against the AVX2 one.
#include "radial_sweep_lanes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

#include "sweep_lanes.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow::detail {
namespace {

bool same(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

// Runs `check(group)` on 200 random groups of lines over a 48 x 48 field: both kinds of side,
// both directions, the foot inside and outside the field, lanes empty or partly swept.
template <class Check>
void for_random_groups(Check check) {
  const auto field = test::mountains(48, 5);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    RadialGroup g;
    g.heights = field->heights.data();
    const bool x_major = trial % 2 == 0;
    g.stride_u = x_major ? 1 : field->width;
    g.stride_v = x_major ? field->width : 1;
    g.size_v = x_major ? field->height : field->width;
    const int size_u = x_major ? field->width : field->height;
    g.sign = trial % 4 < 2 ? 1 : -1;
    g.u_first = static_cast<int>(u01(rng) * (size_u - 1));
    const int columns = g.sign > 0 ? size_u - g.u_first : g.u_first + 1;
    g.v0 = -10 + (g.size_v + 20) * u01(rng);  // the foot inside or outside the field
    g.r_near = u01(rng);
    g.height_scale = trial % 3 == 0 ? 1.5f : 1.0f;
    const double m0 = -1 + 2 * u01(rng), dm = 0.02 + 0.1 * u01(rng);
    for (int l = 0; l < kRadialLanes; ++l) {
      g.m[l] = std::clamp(m0 + l * dm, -1.0, 1.0);
      g.inv_metres[l] = static_cast<float>(1 / std::sqrt(1 + g.m[l] * g.m[l]));
      g.first[l] = static_cast<int>(u01(rng) * columns / 3);
      g.end[l] = l == 7 && trial % 5 == 0
                     ? g.first[l]  // an empty lane
                     : g.first[l] + static_cast<int>(u01(rng) * (columns - g.first[l]));
      g.width = std::max(g.width, g.end[l] + static_cast<int>(u01(rng) * (columns - g.end[l])));
    }
    check(g, trial);
  }
}

TEST(RadialSweepLanes, LanesEqualTheScalarKernel) {
  RadialScratch a, b;
  int compared = 0, finite = 0;
  for_random_groups([&](const RadialGroup& g, int trial) {
    std::vector<float> scalar(static_cast<std::size_t>(g.width) * kRadialLanes, 7.0f),
        lanes(scalar.size(), -7.0f);
    sweep_radial_group_scalar(g, a, scalar.data());
    sweep_radial_group_lanes(g, b, lanes.data());
    for (std::size_t i = 0; i < scalar.size(); ++i) {
      const int k = static_cast<int>(i) / kRadialLanes, l = static_cast<int>(i) % kRadialLanes;
      ASSERT_TRUE(same(scalar[i], lanes[i])) << "trial " << trial << " column " << k << " lane "
                                             << l << ": " << scalar[i] << " vs " << lanes[i];
      const bool swept = k >= g.first[l] && k < g.end[l];
      ASSERT_EQ(std::isnan(lanes[i]), !swept) << "trial " << trial;
      ++compared;
      finite += std::isfinite(lanes[i]);
    }
  });
  EXPECT_GT(finite, 10000);  // measured 14,592
  EXPECT_GT(compared, finite);
}

TEST(RadialSweepLanes, OneScratchServesBothKernels) {
  // A scratch sized by the scalar kernel for a long group (its hulls: one float per column),
  // then used by the lanes for a short one (eight per column, pairs in the AVX-512 copy): each
  // kernel sizes what it needs (an overrun shows under ASan), with the same results as a fresh
  // scratch.
  RadialScratch fresh;
  int compared = 0;
  for_random_groups([&](const RadialGroup& g, int trial) {
    RadialScratch shared;  // new each time: its buffers hold exactly what the scalar kernel sized
    std::vector<float> out(static_cast<std::size_t>(g.width) * kRadialLanes);
    sweep_radial_group_scalar(g, shared, out.data());
    RadialGroup short_group = g;
    for (int l = 0; l < kRadialLanes; ++l)
      short_group.first[l] = 0, short_group.end[l] = std::min(g.width, 2 + trial % 4);
    std::vector<float> reused(static_cast<std::size_t>(g.width) * kRadialLanes),
        expected(reused.size());
    sweep_radial_group_lanes(short_group, shared, reused.data());
    sweep_radial_group_lanes(short_group, fresh, expected.data());
    for (std::size_t i = 0; i < reused.size(); ++i)
      ASSERT_TRUE(same(reused[i], expected[i])) << "trial " << trial << " slot " << i;
    compared += static_cast<int>(reused.size());
  });
  EXPECT_GT(compared, 1000);
}

TEST(RadialSweepLanes, TheAvx512KernelGivesTheAvx2KernelsBits) {
  if (sweep_isa() != SweepIsa::kAvx512)
    GTEST_SKIP() << "this CPU has no AVX-512: only the AVX2 kernel can run";
  RadialScratch a, b;
  int compared = 0;
  for_random_groups([&](const RadialGroup& g, int trial) {
    std::vector<float> avx2(static_cast<std::size_t>(g.width) * kRadialLanes, 7.0f),
        avx512(avx2.size(), -7.0f);
    force_sweep_isa(SweepIsa::kAvx2);
    sweep_radial_group_lanes(g, a, avx2.data());
    force_sweep_isa(SweepIsa::kAvx512);
    sweep_radial_group_lanes(g, b, avx512.data());
    force_sweep_isa(std::nullopt);
    for (std::size_t i = 0; i < avx2.size(); ++i)
      ASSERT_TRUE(same(avx2[i], avx512[i]))
          << "trial " << trial << " slot " << i << ": " << avx2[i] << " vs " << avx512[i];
    compared += static_cast<int>(avx2.size());
  });
  EXPECT_GT(compared, 10000);
}

// Two groups of a side in one call (sixteen lanes in the AVX-512 copy) give what each gives
// alone, bit for bit, and write nothing past either block: the second group's lines further
// along, its columns and width drawn apart from the first's (so that either ends first), and
// a second group whose lanes are all empty.
TEST(RadialSweepLanes, APairOfGroupsGivesEachGroupsBits) {
  RadialScratch pair_scratch, single;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u01(0, 1);
  int compared = 0, finite = 0;
  constexpr float kGuard = 12345.0f;
  constexpr std::size_t kPadding = 64;
  for_random_groups([&](const RadialGroup& a, int trial) {
    RadialGroup b = a;
    b.width = 0;
    const int columns = a.sign > 0 ? 48 - a.u_first : a.u_first + 1;  // the 48 x 48 field
    for (int l = 0; l < kRadialLanes; ++l) {
      b.m[l] = std::clamp(a.m[l] + 0.05 * (l + 1), -1.0, 1.0);
      b.inv_metres[l] = static_cast<float>(1 / std::sqrt(1 + b.m[l] * b.m[l]));
      b.first[l] = static_cast<int>(u01(rng) * columns / 2);
      b.end[l] = trial % 7 == 3 ? b.first[l]  // every lane empty
                                : b.first[l] + static_cast<int>(u01(rng) * (columns - b.first[l]));
      b.width = std::max(b.width, b.end[l] + static_cast<int>(u01(rng) * (columns - b.end[l])));
    }
    if (b.width == 0) b.width = 1;
    auto run = [&](bool as_pair, std::vector<float>& out_a, std::vector<float>& out_b) {
      out_a.assign(static_cast<std::size_t>(a.width) * kRadialLanes + kPadding, kGuard);
      out_b.assign(static_cast<std::size_t>(b.width) * kRadialLanes + kPadding, kGuard);
      if (as_pair) {
        sweep_radial_pair_lanes(a, b, pair_scratch, out_a.data(), out_b.data());
      } else {
        sweep_radial_group_lanes(a, single, out_a.data());
        sweep_radial_group_lanes(b, single, out_b.data());
      }
    };
    std::vector<float> pa, pb, sa, sb;
    run(true, pa, pb);
    run(false, sa, sb);
    for (const auto& [got, want, width] : {std::tuple{&pa, &sa, a.width}, {&pb, &sb, b.width}}) {
      for (std::size_t i = 0; i < got->size(); ++i) {
        ASSERT_TRUE(same((*got)[i], (*want)[i]))
            << "trial " << trial << " slot " << i << ": " << (*got)[i] << " vs " << (*want)[i];
        if (i >= static_cast<std::size_t>(width) * kRadialLanes) {
          ASSERT_EQ((*got)[i], kGuard) << "trial " << trial << ": written past the block";
        }
        finite += std::isfinite((*got)[i]) && (*got)[i] != kGuard;
      }
      compared += static_cast<int>(got->size());
    }
  });
  EXPECT_GT(finite, 20000);
  std::printf("pairs: %d slots compared, %d finite (%s)\n", compared, finite,
              sweep_isa() == SweepIsa::kAvx512 ? "the AVX-512 pair walk"
                                               : "no AVX-512 here: two single walks");
}

}  // namespace
}  // namespace penumbra::terrain_shadow::detail
