// The OEM SH sets ([Ambrosj16] sec. 4.2-4.3) and the eq. 3.15 irradiance matrices.
// Tolerances: each set equals sh::project_equirect of the map with the absent sources' texels
// blackened within 1e-3 of the DC term (sh::project_equirect sums 131,072 texels in float:
// about 4e-4 relative, against this library's double sums); removing a source
// lowers the set's luminous energy (DC luminance) by that source's share within 1e-3 (relative
// to the whole map); n^T M n equals the 3-band SH irradiance within 1e-4 of its DC irradiance
// (003's constants have 6 digits).
#include "penumbra/systems/environment/occluded_environment_maps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "common/random_draws.h"
#include "penumbra/sh/convolution.h"
#include "penumbra/sh/projection.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace sh = penumbra::sh;
namespace t = penumbra::test;

namespace {

constexpr int kMapW = 512, kMapH = 256;

penumbra::data::EnvironmentMap two_sun_map() {
  auto m = t::flat_map(kMapW, kMapH, glm::vec3(0.3f, 0.4f, 0.6f));
  t::add_disc(m, t::dir_deg(60, 35), 3.0f, glm::vec3(3000, 2800, 2500));
  t::add_disc(m, t::dir_deg(250, 10), 4.0f, glm::vec3(800));
  return m;
}

template <class C>  // a sh::CoeffsRgb<N>
double dc_luminance(const C& c) {
  return 179.0 * (0.265 * c[0][0] + 0.670 * c[1][0] + 0.065 * c[2][0]);
}

TEST(OccludedEnvironmentMaps, EachSetIsTheBlackenedMapsProjection) {
  const auto m = two_sun_map();
  const auto d = env::detect_light_sources(m);
  ASSERT_EQ(d.sources.size(), 2u);
  const auto oem = env::build_occluded_environment_maps(m, d);
  ASSERT_EQ(oem.set_count(), 4u);  // 2^n
  ASSERT_EQ(oem.sh3.size(), 4u);
  for (std::size_t mask = 0; mask < 4; ++mask) {
    auto copy = m;
    for (int j = 0; j < 2; ++j) {
      if (mask & (std::size_t{1} << j)) continue;
      for (std::uint32_t i : d.sources[static_cast<std::size_t>(j)].texels)
        for (int c = 0; c < 3; ++c) copy.rgb[3 * i + static_cast<std::size_t>(c)] = 0.0f;
    }
    const auto ref4 = sh::project_equirect<sh::kDefaultBands>(copy.rgb.data(), kMapW, kMapH);
    const auto ref3 = sh::project_equirect<3>(copy.rgb.data(), kMapW, kMapH);
    for (std::size_t c = 0; c < 3; ++c) {
      const float tol = 1e-3f * ref4[c][0];
      for (std::size_t i = 0; i < ref4[c].size(); ++i)
        EXPECT_NEAR(oem.sh[mask][c][i], ref4[c][i], tol) << "mask " << mask << " c " << c;
      for (std::size_t i = 0; i < 9; ++i) EXPECT_NEAR(oem.sh3[mask][c][i], ref3[c][i], tol);
    }
  }
}

TEST(OccludedEnvironmentMaps, RemovingASourceRemovesItsShare) {
  const auto m = two_sun_map();
  const auto d = env::detect_light_sources(m);
  ASSERT_EQ(d.sources.size(), 2u);
  const auto oem = env::build_occluded_environment_maps(m, d);
  const double whole = dc_luminance(oem.sh[3]);
  EXPECT_NEAR(whole,
              dc_luminance(sh::project_equirect<sh::kDefaultBands>(m.rgb.data(), kMapW, kMapH)),
              1e-3 * whole);  // project_equirect sums in float
  for (int j = 0; j < 2; ++j) {
    const double share = d.sources[static_cast<std::size_t>(j)].energy_share;
    const std::size_t without = 3u & ~(std::size_t{1} << j);
    EXPECT_NEAR(whole - dc_luminance(oem.sh[without]), share * whole, 1e-3 * whole) << j;
  }
  EXPECT_NEAR(whole - dc_luminance(oem.sh[0]),
              (d.sources[0].energy_share + d.sources[1].energy_share) * whole, 1e-3 * whole);
}

TEST(OccludedEnvironmentMaps, NoSourceGivesOneSetTheWholeMap) {
  const auto m = t::flat_map(64, 32, glm::vec3(1));
  const auto d = env::detect_light_sources(m);
  ASSERT_TRUE(d.sources.empty());
  const auto oem = env::build_occluded_environment_maps(m, d);
  ASSERT_EQ(oem.set_count(), 1u);
  const auto ref = sh::project_equirect<sh::kDefaultBands>(m.rgb.data(), 64, 32);
  EXPECT_NEAR(oem.sh[0][0][0], ref[0][0], 1e-5f);
}

TEST(OccludedEnvironmentMaps, DetectionOfAnotherMapThrows) {
  const auto m = two_sun_map();
  auto d = env::detect_light_sources(m);
  const auto small = t::flat_map(64, 32, glm::vec3(1), "small.exr");
  EXPECT_THROW(env::build_occluded_environment_maps(small, d), std::invalid_argument);
  d.sources[0].texels.push_back(kMapW * kMapH);  // outside the map
  EXPECT_THROW(env::build_occluded_environment_maps(m, d), std::invalid_argument);
}

// [Ambrosj16] eq. 3.15 against the SH irradiance (Ramamoorthi and Hanrahan's band weights).
TEST(OccludedEnvironmentMaps, IrradianceMatrixMatchesShIrradiance) {
  std::mt19937 rng(15);
  std::normal_distribution<float> g(0.0f, 1.0f);
  sh::CoeffsRgb<3> L{};
  for (auto& c : L)
    for (float& v : c) v = g(rng);
  for (auto& c : L) c[0] = 4.0f;
  const auto M = env::irradiance_matrices(L);
  for (int k = 0; k < 50; ++k) {
    const glm::vec3 n = glm::normalize(penumbra::test::draw_zyx<glm::vec3>(rng, g));
    const glm::vec4 v(n, 1.0f);
    for (std::size_t c = 0; c < 3; ++c) {
      const float e_matrix = glm::dot(v, M[c] * v);
      const float e_sh = sh::evaluate<3>(sh::irradiance_convolve<3>(L[c]), n);
      EXPECT_NEAR(e_matrix, e_sh, 1e-4f * 3.14159f * 4.0f * 0.2821f * 10.0f) << k;
    }
  }
}

}  // namespace
