#include "penumbra/sh/rotation.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "sh_test_util.h"

namespace penumbra::sh {
namespace {

glm::mat3 random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<float> angle(0, 6.2831853f);
  const glm::vec3 axis = test::random_direction(rng);
  return glm::mat3(glm::rotate(glm::mat4(1), angle(rng), axis));
}

// Re-projection of w -> f(R^T w): the definition the rotations must match.
template <int N>
Coeffs<N> reproject_rotated(const Coeffs<N>& f, const glm::mat3& r) {
  const glm::mat3 rt = glm::transpose(r);
  return project<N>([&](const glm::vec3& d) { return evaluate<N>(f, rt * d); },
                    SphereQuadrature::gauss(N + 1, 2 * N + 2));
}

template <int N>
void check_general_rotation(std::uint32_t seed) {
  std::mt19937 rng(seed);
  for (int t = 0; t < 10; ++t) {
    const glm::mat3 r = random_rotation(rng);
    const auto f = test::random_coeffs<N>(rng);
    EXPECT_LT(test::rel_l2<N>(Rotation<N>(r).apply(f), reproject_rotated<N>(f, r)), 2e-5f)
        << N << " bands, trial " << t;
  }
}

TEST(Rotation, GeneralRotationEqualsReprojection) {
  check_general_rotation<2>(10);
  check_general_rotation<3>(11);
  check_general_rotation<4>(12);
  check_general_rotation<5>(13);
  check_general_rotation<6>(14);
}

TEST(Rotation, ZRotationEqualsGeneralAndReprojection) {
  std::mt19937 rng(15);
  const auto f = test::random_coeffs<5>(rng);
  const float a = 0.83f;
  const glm::mat3 rz = glm::mat3(glm::rotate(glm::mat4(1), a, glm::vec3(0, 0, 1)));
  EXPECT_LT(test::rel_l2<5>(rotate_z<5>(f, a), Rotation<5>(rz).apply(f)), 2e-5f);
  EXPECT_LT(test::rel_l2<5>(rotate_z<5>(f, a), reproject_rotated<5>(f, rz)), 2e-5f);
}

TEST(Rotation, ComposesAndPreservesNorm) {
  std::mt19937 rng(16);
  const glm::mat3 a = random_rotation(rng), b = random_rotation(rng);
  const auto f = test::random_coeffs<4>(rng);
  const auto ab = Rotation<4>(b).apply(Rotation<4>(a).apply(f));
  EXPECT_LT(test::rel_l2<4>(ab, Rotation<4>(b * a).apply(f)), 1e-5f);
  EXPECT_NEAR(dot<4>(ab, ab), dot<4>(f, f), 1e-4f);
}

TEST(Rotation, ZonalRotationPutsTheLobeOnTheAxis) {
  std::mt19937 rng(17);
  const Zonal<4> z = {1.0f, 0.7f, 0.3f, -0.2f};
  for (int t = 0; t < 10; ++t) {
    const glm::vec3 axis = test::random_direction(rng);
    const auto rotated = rotate_zh<4>(z, axis);
    EXPECT_NEAR(evaluate<4>(rotated, axis), evaluate<4>(zonal_to_sh<4>(z), {0, 0, 1}), 1e-5f);
    // Same as the general rotation taking +z to axis.
    const glm::vec3 zaxis(0, 0, 1);
    const glm::vec3 c = glm::cross(zaxis, axis);
    if (glm::length(c) < 1e-3f) continue;
    const glm::mat3 r = glm::mat3(glm::rotate(glm::mat4(1), std::acos(glm::dot(zaxis, axis)), glm::normalize(c)));
    EXPECT_LT(test::rel_l2<4>(rotated, Rotation<4>(r).apply(zonal_to_sh<4>(z))), 2e-5f);
  }
}

}  // namespace
}  // namespace penumbra::sh
