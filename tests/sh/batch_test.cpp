#include "penumbra/sh/batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include "common/stability.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "sh_test_util.h"

namespace penumbra::sh {
namespace {

// The batch against the scalar functions: |batch - scalar| <= kTol max(|scalar|, 1e-3) per
// coefficient, NaN nowhere unless in both. The same generated code runs in both, so the
// differences are the compiler's multiply-add fusing at most (measured: printed by each test).
constexpr float kTol = 1e-5f;

template <int N>
float worst_difference(const Coeffs<N>& batch, const Coeffs<N>& scalar) {
  float worst = 0;
  for (int i = 0; i < N * N; ++i) {
    if (std::isnan(batch[i]) || std::isnan(scalar[i])) {
      if (std::isnan(batch[i]) != std::isnan(scalar[i]))
        return std::numeric_limits<float>::infinity();
      continue;
    }
    worst =
        std::max(worst, std::fabs(batch[i] - scalar[i]) / std::max(std::fabs(scalar[i]), 1e-3f));
  }
  return worst;
}

// HYB's number of squarings for `f`, as exp_hyb computes it.
template <int N>
int squarings(const Coeffs<N>& f) {
  float norm2 = 0;
  for (int i = 1; i < N * N; ++i) norm2 += f[i] * f[i];
  const float norm = std::sqrt(norm2);
  return norm > kHybOlNorm && std::isfinite(norm)
             ? static_cast<int>(std::ceil(std::log2(norm / kHybOlNorm)))
             : 0;
}

// Runs exp_hyb_batch and exp_visibility_batch over `inputs` (a multiple of kBatch) and returns
// the worst difference to the scalar functions; `mixed` counts the batches whose lanes take
// different numbers of squarings.
template <int N>
float compare_exponentials(const std::vector<Coeffs<N>>& inputs, int& mixed) {
  float worst = 0;
  mixed = 0;
  for (std::size_t first = 0; first + kBatch <= inputs.size(); first += kBatch) {
    CoeffsBatch<N> in, hyb, vis;
    std::set<int> ks;
    for (int l = 0; l < kBatch; ++l) {
      in.set(l, inputs[first + l]);
      ks.insert(squarings<N>(inputs[first + l]));
    }
    mixed += ks.size() > 1;
    exp_hyb_batch<N>(in, hyb);
    exp_visibility_batch<N>(in, vis);
    for (int l = 0; l < kBatch; ++l) {
      const Coeffs<N>& f = inputs[first + l];
      worst = std::max(worst, worst_difference<N>(hyb.get(l), exp_hyb<N>(f)));
      worst = std::max(worst, worst_difference<N>(vis.get(l), exp_visibility<N>(f)));
    }
  }
  return worst;
}

template <int N>
void random_inputs_match() {
  std::mt19937 rng(7 + N);
  std::vector<Coeffs<N>> inputs;
  const float scales[] = {0.001f, 0.05f, 0.3f, 1.0f, 3.0f, 10.0f};
  for (int i = 0; i < 40 * kBatch; ++i)  // scales mixed within each batch
    inputs.push_back(test::random_coeffs<N>(rng, scales[(i * 5 + i / 7) % 6]));
  int mixed = 0;
  const float worst = compare_exponentials<N>(inputs, mixed);
  std::printf("%d bands, random inputs: worst difference %.3g, %d of 40 batches with mixed k\n", N,
              worst, mixed);
  EXPECT_LE(worst, kTol);
  EXPECT_GE(mixed, 30);
}

TEST(ShBatch, ExponentialsMatchScalarOnRandomInputs) {
  random_inputs_match<3>();
  random_inputs_match<4>();
  random_inputs_match<5>();
  random_inputs_match<6>();
}

// Blocker-like sums: 1-16 caps of log eps -3 at sin 0.1-0.6 (as exp_log_test), so a batch mixes
// receivers under few and under many blockers (0 to about 6 squarings).
TEST(ShBatch, ExponentialsMatchScalarOnBlockerSums) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> s(0.1f, 0.6f);
  std::vector<Coeffs<4>> inputs;
  std::set<int> all_k;
  for (int i = 0; i < 64 * kBatch; ++i) {
    Coeffs<4> sum{};
    const int count = i % 17;  // 0: open sky
    for (int b = 0; b < count; ++b) {
      const glm::vec3 axis = test::random_direction(rng);  // before s: GCC's order
      const auto v = rotate_zh<4>(zh_sphere_log_visibility<4>(s(rng), 1.0f, -3.0f), axis);
      for (int c = 0; c < 16; ++c) sum[c] += v[c];
    }
    inputs.push_back(sum);
    all_k.insert(squarings<4>(sum));
  }
  int mixed = 0;
  const float worst = compare_exponentials<4>(inputs, mixed);
  std::printf("blocker sums: worst difference %.3g, squarings %d to %d, %d of 64 batches mixed\n",
              worst, *all_k.begin(), *all_k.rbegin(), mixed);
  EXPECT_LE(worst, kTol);
  EXPECT_GE(mixed, 56);
  EXPECT_GE(all_k.size(), 4u);
}

// NaN, infinite and huge lanes (exp_visibility's clamp and its fallback) next to ordinary ones:
// every lane as the scalar function, and an ordinary lane untouched by its neighbours.
TEST(ShBatch, NonFiniteAndHugeInputsFallBackAsScalar) {
  PENUMBRA_STABILITY("NaN, infinite and huge SH lanes beside ordinary ones",
                     "each lane as the scalar function; visibility finite and within [0, 1]",
                     "exp_visibility's clamp and fallback");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::mt19937 rng(3);
  const Coeffs<4> ordinary = test::random_coeffs<4>(rng, 0.5f);
  std::vector<Coeffs<4>> odd;
  auto with = [&](int i, float x) {
    Coeffs<4> f = ordinary;
    f[i] = x;
    return f;
  };
  odd.push_back(with(0, nan));
  odd.push_back(with(5, nan));
  odd.push_back(with(0, inf));
  odd.push_back(with(0, -inf));
  odd.push_back(with(3, inf));
  odd.push_back(with(3, -inf));
  odd.push_back(with(7, 1e4f));   // ~17 squarings: overflows, the clamp zeroes it
  odd.push_back(with(7, 1e20f));  // the norm's square overflows
  odd.push_back(with(0, 1e4f));   // e^DC overflows
  odd.push_back(with(0, -1e4f));  // e^DC underflows
  odd.push_back(with(2, 40.0f));  // large but finite after 9 squarings: the rescaling branch
  std::vector<Coeffs<4>> inputs;
  for (const Coeffs<4>& f : odd) {  // each odd input in every lane, ordinary ones around it
    for (int lane = 0; lane < kBatch; ++lane)
      for (int l = 0; l < kBatch; ++l) inputs.push_back(l == lane ? f : ordinary);
  }
  int mixed = 0;
  const float worst = compare_exponentials<4>(inputs, mixed);
  std::printf("non-finite / huge lanes: worst difference %.3g\n", worst);
  EXPECT_LE(worst, kTol);
  // The visibility is always finite and within what a [0, 1] function can have.
  for (const Coeffs<4>& f : odd) {
    CoeffsBatch<4> in, v;
    for (int l = 0; l < kBatch; ++l) in.set(l, f);
    exp_visibility_batch<4>(in, v);
    const Coeffs<4> out = v.get(3);
    float rest2 = 0;
    for (int i = 1; i < 16; ++i) {
      EXPECT_TRUE(std::isfinite(out[i]));
      rest2 += out[i] * out[i];
    }
    EXPECT_GE(out[0], 0.0f);
    EXPECT_LE(out[0], 1.0f / 0.28209479177387814f * 1.00001f);
    EXPECT_LE(rest2,
              std::max(0.0f, out[0] / 0.28209479177387814f - out[0] * out[0]) * 1.0001f + 1e-6f);
  }
}

template <int N>
float product_and_rotation_worst() {
  std::mt19937 rng(5 + N);
  float worst = 0;
  Zonal<N> lobe = zh_clamped_cosine<N>();
  for (int trial = 0; trial < 20; ++trial) {
    CoeffsBatch<N> f, g, p, r;
    DirBatch axes;
    std::vector<glm::vec3> dirs;
    for (int l = 0; l < kBatch; ++l) {
      f.set(l, test::random_coeffs<N>(rng));
      g.set(l, test::random_coeffs<N>(rng));
      dirs.push_back(test::random_direction(rng));
      axes.set(l, dirs.back());
    }
    product_batch<N>(f, g, p);
    rotate_zh_batch<N>(lobe, axes, r);
    for (int l = 0; l < kBatch; ++l) {
      worst = std::max(worst, worst_difference<N>(p.get(l), product<N>(f.get(l), g.get(l))));
      worst = std::max(worst, worst_difference<N>(r.get(l), rotate_zh<N>(lobe, dirs[l])));
    }
  }
  return worst;
}

TEST(ShBatch, ProductAndRotatedZonalMatchScalar) {
  const float worst = std::max({product_and_rotation_worst<2>(), product_and_rotation_worst<3>(),
                                product_and_rotation_worst<4>(), product_and_rotation_worst<5>(),
                                product_and_rotation_worst<6>()});
  std::printf("product_batch, rotate_zh_batch: worst difference %.3g\n", worst);
  EXPECT_LE(worst, kTol);
}

// irradiance_batch over a count that is not a multiple of kBatch (a padded last batch) against
// exp_visibility + product with the rotated clamped cosine + three dots, per receiver.
template <int N>
void irradiance_matches(std::size_t count) {
  std::mt19937 rng(17 + static_cast<unsigned>(count));
  std::vector<Coeffs<N>> logs;
  std::vector<glm::vec3> normals;
  CoeffsRgb<N> sky{};
  for (auto& c : sky) c = test::random_coeffs<N>(rng, 0.3f);
  for (int c = 0; c < 3; ++c) sky[c][0] = 3.0f + static_cast<float>(c);
  for (std::size_t i = 0; i < count; ++i) {
    logs.push_back(test::random_coeffs<N>(rng, i % 3 == 0 ? 0.05f : 1.5f));
    logs.back()[0] = -2.0f * static_cast<float>(i % 4);
    normals.push_back(test::random_direction(rng));
  }
  const Zonal<N> lobe = zh_clamped_cosine<N>();
  std::vector<glm::vec3> e(count, glm::vec3(-1));
  std::vector<Coeffs<N>> vis(count), vis_only(count);
  irradiance_batch<N>(sky, lobe, logs, normals, e, vis);
  exp_visibility_batch<N>(std::span<const Coeffs<N>>(logs), std::span<Coeffs<N>>(vis_only));
  float worst_v = 0, worst_e = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const Coeffs<N> v = exp_visibility<N>(logs[i]);
    const Coeffs<N> t = product<N>(v, rotate_zh<N>(lobe, normals[i]));
    worst_v =
        std::max({worst_v, worst_difference<N>(vis[i], v), worst_difference<N>(vis_only[i], v)});
    for (int c = 0; c < 3; ++c) {
      const float want = dot<N>(sky[c], t);
      worst_e = std::max(worst_e, std::fabs(e[i][c] - want) / std::max(std::fabs(want), 1e-3f));
    }
  }
  std::printf("%d bands, %zu receivers: visibility worst %.3g, irradiance worst %.3g\n", N, count,
              worst_v, worst_e);
  EXPECT_LE(worst_v, kTol);
  EXPECT_LE(worst_e, kTol);
}

TEST(ShBatch, IrradianceMatchesScalarWithATail) {
  irradiance_matches<4>(8 * 25 + 5);
  irradiance_matches<4>(3);
  irradiance_matches<3>(8 * 4 + 7);
  irradiance_matches<5>(8 * 4 + 1);
  irradiance_matches<4>(0);
}

// The depth limit's evaluations: one vector at many directions, counts around a batch.
TEST(ShBatch, EvaluateMatchesScalarWithATail) {
  std::mt19937 rng(23);
  float worst = 0;
  for (const std::size_t count : {0u, 1u, 7u, 8u, 9u, 17u, 64u}) {
    const Coeffs<4> f = test::random_coeffs<4>(rng, 2.0f);
    std::vector<glm::vec3> dirs;
    for (std::size_t i = 0; i < count; ++i) dirs.push_back(test::random_direction(rng));
    std::vector<float> out(count, -1.0f);
    evaluate_batch<4>(f, dirs, out);
    for (std::size_t i = 0; i < count; ++i) {
      const float want = evaluate<4>(f, dirs[i]);
      worst = std::max(worst, std::fabs(out[i] - want) / std::max(std::fabs(want), 1e-3f));
    }
  }
  std::printf("evaluate_batch: worst difference %.3g\n", worst);
  EXPECT_LE(worst, kTol);
}

TEST(ShBatch, SizeMismatchThrows) {
  std::vector<Coeffs<4>> logs(9), vis(8);
  std::vector<glm::vec3> normals(9), e(9);
  EXPECT_THROW(irradiance_batch<4>({}, zh_clamped_cosine<4>(), logs, normals, e, vis),
               std::invalid_argument);
  EXPECT_THROW(exp_visibility_batch<4>(std::span<const Coeffs<4>>(logs), std::span<Coeffs<4>>(vis)),
               std::invalid_argument);
  std::vector<float> values(8);
  EXPECT_THROW(evaluate_batch<4>(Coeffs<4>{}, normals, values), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::sh
