// Terrain group, the transfer part of the update alone: horizons -> wedge visibility ->
// transfer for every texel of the 256 x 256 field, as TerrainShadowing does it (32 azimuths,
// 4 bands, [Meier13] eq. 4.19 and 4.21).
//
//   part/transfer/n_phi:32/bands:4
#include <tbb/parallel_for.h>

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

void BM_Transfer(benchmark::State& state) {
  constexpr int N = 4;
  const auto field = scene_field(kSize);
  ts::TerrainShadowing<N> shadowing;
  shadowing.update(field, tbr::kHeightScale);
  const ts::WedgeTable<N> table(32, ts::WedgeDomain::kHemisphere, 64);
  const ts::HorizonGrid& horizons = shadowing.horizons();
  const std::vector<glm::vec3>& normals = shadowing.normals();
  std::vector<sh::Coeffs<N>> transfer(normals.size());
  for (auto _ : state) {
    tbb::parallel_for(0, kSize, [&](int y) {
      for (int x = 0; x < kSize; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * kSize + x;
        transfer[i] = ts::diffuse_transfer<N>(table.visibility(horizons.texel(x, y)), normals[i]);
      }
    });
    benchmark::DoNotOptimize(transfer.data());
  }
  const double texels = static_cast<double>(kSize) * kSize;
  set_work(state, texels * (32 * wedge_ops(N) + transfer_ops<N>()),
           texels * (32 * 4 + 12 + N * N * 4));
}

}  // namespace

void register_transfer_part() {
  pb::add("part/transfer/n_phi:32/bands:4", runs(10, kCaseReps), BM_Transfer);
  register_case("part/transfer/n_phi:32/bands:4", "transfer alone (wedges + V*C), n_phi=32",
                "transfer", "{\"n_phi\": 32, \"bands\": 4, \"part\": \"transfer\"}", kSize,
                std::nullopt);
}

}  // namespace penumbra::terrain_bench
