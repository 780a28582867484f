// Terrain group, shading only: a rotating environment (rotate_z of the SH radiance) shaded from
// the stored transfer (shade_environment), 256 x 256, 4 bands; and its same-run baseline, one
// streaming read of the stored transfer vectors.
//
//   shade/rotating_env
//   baseline/shade_read_transfer
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/rotation.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

void BM_Shade(benchmark::State& state) {
  constexpr int N = 4;
  auto& shadowing = shadowing_for<N>("shade", ts::TerrainShadowConfig{}, kSize);
  const sh::CoeffsRgb<N>& env = environment_sh<N>();
  std::vector<glm::vec3> irradiance;
  float angle = 0;
  for (auto _ : state) {
    angle += 0.01f;
    const sh::CoeffsRgb<N> rotated = {sh::rotate_z<N>(env[0], angle),
                                      sh::rotate_z<N>(env[1], angle),
                                      sh::rotate_z<N>(env[2], angle)};
    shadowing.shade_environment(rotated, irradiance);
    benchmark::DoNotOptimize(irradiance.data());
  }
  const double texels = static_cast<double>(kSize) * kSize;
  set_work(state, texels * 3.0 * N * N, texels * (N * N * 4 + 12));
}

// Same-run baseline of the shading: one streaming read of the stored transfer vectors.
void BM_ShadeReadBaseline(benchmark::State& state) {
  auto& shadowing = shadowing_for<4>("shade", ts::TerrainShadowConfig{}, kSize);
  const auto& t = shadowing.transfer();
  const float* p = t.data()->data();
  const std::size_t n = t.size() * t[0].size();
  for (auto _ : state) benchmark::DoNotOptimize(stream_read(p, n));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(n * sizeof(float)));
}

}  // namespace

void register_shade() {
  pb::add("shade/rotating_env", runs(50, kCaseReps), BM_Shade);
  register_case("shade/rotating_env", "shading only (rotate_z + shade_environment)", "shade",
                "{\"bands\": 4}", kSize, std::nullopt);
  pb::add("baseline/shade_read_transfer", runs(50, kCaseReps), BM_ShadeReadBaseline);
}

}  // namespace penumbra::terrain_bench
