// Terrain group, the horizon part of the update alone, 256 x 256, 32 azimuths:
//
//   part/pyramid/ls:4                          the height pyramid the march reads
//   part/horizons/sweep/n_phi:32               horizon sweep over every texel (the default)
//   part/horizons/march/n_phi:32/ls:4/lo:2     horizon march on the pyramid, as TerrainShadowing
//                                              runs it: bands of 8 rows in parallel
//   part/horizons/sweep_avx2/n_phi:32          the sweep with its AVX2 copy forced (what a CPU
//                                              without AVX-512 runs; the same floats)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "sweep_lanes.h"  // force_sweep_isa
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

void BM_Pyramid(benchmark::State& state) {
  const auto field = scene_field(kSize);
  ts::HeightPyramid pyramid;
  ts::PyramidParams params;
  params.level_step = 4;
  pyramid.build(*field, tbr::kHeightScale, params);
  for (auto _ : state) {
    pyramid.build(*field, tbr::kHeightScale, params);
    benchmark::DoNotOptimize(pyramid.level_data(0));
  }
  const double samples = static_cast<double>(kSize) * kSize * pyramid.levels();
  set_work(state, samples * kPyramidOpsPerSample, samples * 4);
}

void BM_HorizonsSweep(benchmark::State& state) {
  const auto field = scene_field(kSize);
  const ts::HorizonParams p = env_horizon_params(32);
  ts::HorizonGrid grid;
  ts::SweepWorkspace workspace;  // as the system keeps one: buffers reused from call to call
  ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid, workspace);
  for (auto _ : state) {
    ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid, workspace);
    benchmark::DoNotOptimize(grid.angles.data());
  }
  const double pairs = static_cast<double>(kSize) * kSize * p.azimuths;
  set_work(state, pairs * kSweepOpsPerPair, pairs * 4);
}

// The same with the AVX2 copy of the sweep's kernels forced (on a CPU without AVX-512 it runs
// anyway, and this case equals the one above).
void BM_HorizonsSweepAvx2(benchmark::State& state) {
  ts::detail::force_sweep_isa(ts::detail::SweepIsa::kAvx2);
  BM_HorizonsSweep(state);
  ts::detail::force_sweep_isa(std::nullopt);
}

void BM_HorizonsMarch(benchmark::State& state) {
  const auto field = scene_field(kSize);
  const ts::HorizonParams p = env_horizon_params(32);
  ts::HeightPyramid pyramid;
  pyramid.build(*field, tbr::kHeightScale, ts::PyramidParams{4});
  ts::MarchParams march;
  march.level_offset = 2;
  ts::HorizonGrid grid;
  ts::march_horizons(pyramid, p, march, ts::TexelRect::all(*field), grid);
  // As TerrainShadowing runs it: bands of 8 rows in parallel (one call is single-threaded).
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, kSize, 8), [&](const tbb::blocked_range<int>& r) {
      ts::march_horizons(pyramid, p, march, {0, r.begin(), kSize, r.end()}, grid);
    });
    benchmark::DoNotOptimize(grid.angles.data());
  }
  const double pairs = static_cast<double>(kSize) * kSize * p.azimuths;
  set_work(state, pairs * (kMarchOpsPerSample * pyramid.levels() + kAtanOps), pairs * 4);
}

}  // namespace

void register_horizon_parts() {
  pb::add("part/pyramid/ls:4", runs(20, kCaseReps), BM_Pyramid);
  register_case("part/pyramid/ls:4", "pyramid build ls=4", "pyramid", "{\"ls\": 4}", kSize,
                std::nullopt);
  pb::add("part/horizons/sweep/n_phi:32", runs(10, kCaseReps), BM_HorizonsSweep);
  register_case("part/horizons/sweep/n_phi:32", "horizons alone, sweep n_phi=32", "sweep",
                "{\"n_phi\": 32, \"part\": \"horizons\"}", kSize, std::nullopt);
  pb::add("part/horizons/sweep_avx2/n_phi:32", runs(5, kCaseReps), BM_HorizonsSweepAvx2);
  register_case("part/horizons/sweep_avx2/n_phi:32", "AVX2 copy forced: horizons, sweep n_phi=32",
                "sweep", "{\"n_phi\": 32, \"part\": \"horizons\", \"isa\": \"avx2\"}", kSize,
                std::nullopt);
  pb::add("part/horizons/march/n_phi:32/ls:4/lo:2", runs(5, kCaseReps), BM_HorizonsMarch);
  register_case("part/horizons/march/n_phi:32/ls:4/lo:2", "horizons alone, march ls=4 lo=2",
                "march", "{\"n_phi\": 32, \"ls\": 4, \"lo\": 2, \"part\": \"horizons\"}", kSize,
                std::nullopt);
}

}  // namespace penumbra::terrain_bench
