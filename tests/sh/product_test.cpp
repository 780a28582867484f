#include "penumbra/sh/product.h"

#include <gtest/gtest.h>

#include "sh_test_util.h"

namespace penumbra::sh {
namespace {

// Projection of the pointwise product onto N bands, by a quadrature exact for it.
template <int N>
Coeffs<N> projected_product(const Coeffs<N>& f, const Coeffs<N>& g) {
  return project<N>([&](const glm::vec3& d) { return evaluate<N>(f, d) * evaluate<N>(g, d); },
                    SphereQuadrature::gauss(2 * N, 4 * N));
}

template <int N>
void check_product(std::uint32_t seed) {
  std::mt19937 rng(seed);
  for (int t = 0; t < 5; ++t) {
    const auto f = test::random_coeffs<N>(rng), g = test::random_coeffs<N>(rng);
    const auto p = product<N>(f, g);
    EXPECT_LT(test::rel_l2<N>(p, projected_product<N>(f, g)), 2e-5f) << N << " bands";
    EXPECT_LT(test::rel_l2<N>(p, product_sparse<N>(f, g)), 2e-6f) << N << " bands";
    EXPECT_LT(test::rel_l2<N>(square<N>(f), product<N>(f, f)), 2e-6f) << N << " bands";
  }
}

TEST(Product, EqualsProjectionOfPointwiseProduct) {
  check_product<2>(20);
  check_product<3>(21);
  check_product<4>(22);
  check_product<5>(23);
  check_product<6>(24);
}

TEST(Product, TruncationErrorIsWhatTheBandsCannotHold) {
  // The N-band product is the orthogonal projection of the true product f g, whose bands reach
  // 2N - 2. So |fg - p|^2 = |fg|^2 - |p|^2 (Parseval): the only error is the truncation.
  std::mt19937 rng(25);
  const auto f = test::random_coeffs<4>(rng), g = test::random_coeffs<4>(rng);
  const auto p = product<4>(f, g);
  double err = 0, norm = 0;
  const auto& q = test::fine_quadrature();
  for (std::size_t i = 0; i < q.directions.size(); ++i) {
    const double exact = double(evaluate<4>(f, q.directions[i])) * evaluate<4>(g, q.directions[i]);
    const double approx = evaluate<4>(p, q.directions[i]);
    err += (exact - approx) * (exact - approx) * q.weights[i];
    norm += exact * exact * q.weights[i];
  }
  const double held = dot<4>(p, p);
  EXPECT_NEAR(err, norm - held, 1e-3 * norm);
  EXPECT_GT(err, 0.05 * norm) << "random 4-band inputs put real energy above band 3";
}

TEST(Product, ConstantIsTheIdentity) {
  std::mt19937 rng(26);
  const auto f = test::random_coeffs<5>(rng);
  Coeffs<5> one{};
  one[0] = 3.5449077f;  // sqrt(4 pi): the function 1
  EXPECT_LT(test::rel_l2<5>(product<5>(f, one), f), 2e-6f);
}

TEST(Product, TensorSizes) {
  // Counts of non-zero Gamma_ijk (i, j, k < N^2): fixed by the basis, a change means the
  // generator or its conventions changed.
  EXPECT_EQ(gaunt_entry_count<2>(), 10);
  EXPECT_EQ(gaunt_entry_count<3>(), 83);
  EXPECT_EQ(gaunt_entry_count<4>(), 353);
}

}  // namespace
}  // namespace penumbra::sh
