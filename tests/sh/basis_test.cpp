#include "penumbra/sh/basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "penumbra/sh/lanes.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "sh_test_util.h"

namespace penumbra::sh {
namespace {
// The first 16 basis functions as printed in [Ambrosj16] appendix A.
std::array<float, 16> appendix_a(float x, float y, float z) {
  return {0.5f * std::sqrt(1 / kPi),
          std::sqrt(3 / (4 * kPi)) * y,
          std::sqrt(3 / (4 * kPi)) * z,
          std::sqrt(3 / (4 * kPi)) * x,
          0.5f * std::sqrt(15 / kPi) * x * y,
          0.5f * std::sqrt(15 / kPi) * y * z,
          0.25f * std::sqrt(5 / kPi) * (-x * x - y * y + 2 * z * z),
          0.5f * std::sqrt(15 / kPi) * z * x,
          0.25f * std::sqrt(15 / kPi) * (x * x - y * y),
          0.25f * std::sqrt(35 / (2 * kPi)) * (3 * x * x - y * y) * y,
          0.5f * std::sqrt(105 / kPi) * x * y * z,
          0.25f * std::sqrt(21 / (2 * kPi)) * y * (4 * z * z - x * x - y * y),
          0.25f * std::sqrt(7 / kPi) * z * (2 * z * z - 3 * x * x - 3 * y * y),
          0.25f * std::sqrt(21 / (2 * kPi)) * x * (4 * z * z - x * x - y * y),
          0.25f * std::sqrt(105 / kPi) * z * (x * x - y * y),
          0.25f * std::sqrt(35 / (2 * kPi)) * x * (x * x - 3 * y * y)};
}

TEST(Basis, MatchesAppendixAConvention) {
  std::mt19937 rng(1);
  for (int t = 0; t < 200; ++t) {
    const glm::vec3 d = test::random_direction(rng);
    const auto expected = appendix_a(d.x, d.y, d.z);
    const auto got = eval_basis<4>(d);
    for (int i = 0; i < 16; ++i) EXPECT_NEAR(got[i], expected[i], 2e-6f) << "i=" << i;
  }
}

TEST(Basis, BandOneOrderIsYZX) {
  const float k = std::sqrt(3 / (4 * kPi));
  EXPECT_NEAR(eval_basis<2>({0, 1, 0})[index(1, -1)], k, 1e-6f);
  EXPECT_NEAR(eval_basis<2>({0, 0, 1})[index(1, 0)], k, 1e-6f);
  EXPECT_NEAR(eval_basis<2>({1, 0, 0})[index(1, 1)], k, 1e-6f);
}

template <int N>
void check_orthonormal() {
  const SphereQuadrature q = SphereQuadrature::gauss(N + 1, 2 * N + 2);
  double gram[N * N][N * N] = {};
  for (std::size_t d = 0; d < q.directions.size(); ++d) {
    const auto y = eval_basis<N>(q.directions[d]);
    for (int i = 0; i < N * N; ++i) {
      for (int j = 0; j < N * N; ++j) gram[i][j] += double(y[i]) * y[j] * q.weights[d];
    }
  }
  for (int i = 0; i < N * N; ++i) {
    for (int j = 0; j < N * N; ++j)
      EXPECT_NEAR(gram[i][j], i == j ? 1.0 : 0.0, 2e-5) << i << "," << j;
  }
}

TEST(Basis, OrthonormalForEveryBandCount) {
  check_orthonormal<2>();
  check_orthonormal<3>();
  check_orthonormal<4>();
  check_orthonormal<5>();
  check_orthonormal<6>();
}

TEST(Basis, BatchMatchesScalarAndEvaluateMatchesDot) {
  std::mt19937 rng(2);
  constexpr int kDirs = 37;
  float xs[kDirs], ys[kDirs], zs[kDirs];
  for (int d = 0; d < kDirs; ++d) {
    const glm::vec3 v = test::random_direction(rng);
    xs[d] = v.x;
    ys[d] = v.y;
    zs[d] = v.z;
  }
  float batch[36 * kDirs];
  eval_basis_batch<6>(xs, ys, zs, kDirs, batch);
  const auto f = test::random_coeffs<6>(rng);
  for (int d = 0; d < kDirs; ++d) {
    const auto y = eval_basis<6>({xs[d], ys[d], zs[d]});
    for (int i = 0; i < 36; ++i) EXPECT_EQ(batch[i * kDirs + d], y[i]);
    Coeffs<6> yc;
    std::copy(y.begin(), y.end(), yc.begin());
    EXPECT_NEAR(evaluate<6>(f, {xs[d], ys[d], zs[d]}), dot<6>(f, yc), 1e-5f);
  }
}

// add_cap_lanes: eight caps of different sizes and axes, each the rotated cap indicator
// (zh_cap + rotate_zh) times its scale; a lane with scale 0 adds nothing.
TEST(Basis, CapLanesMatchRotatedCapIndicator) {
  std::mt19937 rng(5);
  alignas(32) float x[8], y[8], z[8], c[8], scale[8];
  float angle[8];
  for (int l = 0; l < 8; ++l) {
    const glm::vec3 v = test::random_direction(rng);
    x[l] = v.x, y[l] = v.y, z[l] = v.z;
    angle[l] = 0.05f + 0.4f * static_cast<float>(l);  // up to 2.85 rad: past the hemisphere
    c[l] = std::cos(angle[l]);
    scale[l] = l == 3 ? 0.0f : -1.6f + 0.1f * static_cast<float>(l);
  }
  Lanes acc[25];
  for (Lanes& a : acc) a = splat(0.5f);  // adds to what is there
  add_cap_lanes<5>(load_lanes(x), load_lanes(y), load_lanes(z), load_lanes(c), load_lanes(scale),
                   acc);
  for (int l = 0; l < 8; ++l) {
    const Coeffs<5> cap = rotate_zh<5>(zh_cap<5>(angle[l]), glm::vec3(x[l], y[l], z[l]));
    for (int i = 0; i < 25; ++i) {
      alignas(32) float out[8];
      store_lanes(acc[i], out);
      EXPECT_NEAR(out[l], 0.5f + scale[l] * cap[i], 2e-5f) << "lane " << l << " coeff " << i;
    }
  }
}

}  // namespace
}  // namespace penumbra::sh
