// Terrain group, the transfer part of the update alone: horizons -> transfer for every texel of
// the 256 x 256 field, as TerrainShadowing does it (32 azimuths, 4 bands): the exact transfer
// (the default: tangent planes, wedges at 5 bands, couplings; transfer.h) and the thesis's
// truncated product (wedges at 4 bands, V * C; [Meier13] eq. 4.19 and 4.21).
//
//   part/transfer/n_phi:32/bands:4
//   part/transfer/n_phi:32/bands:4/transfer:truncated
#include <tbb/parallel_for.h>

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

constexpr int kAzimuths = 32;

void BM_Transfer(benchmark::State& state, bool exact) {
  constexpr int N = 4;
  const auto field = scene_field(kSize);
  ts::TerrainShadowing<N> shadowing;
  shadowing.update(field, tbr::kHeightScale);
  const ts::WedgeTable<N> table(kAzimuths, ts::WedgeDomain::kHemisphere, 64);
  const ts::WedgeTable<N + 1> table_exact(kAzimuths, ts::WedgeDomain::kHemisphere, 64);
  const ts::AzimuthFrame frame(kAzimuths);
  const ts::HorizonGrid& horizons = shadowing.horizons();
  const std::vector<glm::vec3>& normals = shadowing.normals();
  std::vector<sh::Coeffs<N>> transfer(normals.size());
  for (auto _ : state) {
    tbb::parallel_for(0, kSize, [&](int y) {
      float raised[kAzimuths];
      sh::Coeffs<N + 1> vis[8];  // as TerrainShadowing: the couplings eight texels at a time
      for (int x = 0; x < kSize; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * kSize + x;
        if (exact) {
          frame.raise_to_tangent_plane(horizons.texel(x, y), normals[i], raised);
          vis[x % 8] = table_exact.visibility(raised);
          if (x % 8 == 7)  // kSize is a multiple of 8
            ts::exact_diffuse_transfer_8<N>(vis, &normals[i - 7], &transfer[i - 7]);
        } else {
          transfer[i] = ts::diffuse_transfer<N>(table.visibility(horizons.texel(x, y)), normals[i]);
        }
      }
    });
    benchmark::DoNotOptimize(transfer.data());
  }
  const double texels = static_cast<double>(kSize) * kSize;
  set_work(state,
           texels * (exact ? exact_transfer_ops(N, kAzimuths)
                           : kAzimuths * wedge_ops(N) + transfer_ops<N>()),
           texels * (kAzimuths * 4 + 12 + N * N * 4));
}

}  // namespace

void register_transfer_part() {
  pb::add("part/transfer/n_phi:32/bands:4", runs(10, kCaseReps), BM_Transfer, true);
  register_case("part/transfer/n_phi:32/bands:4",
                "transfer alone (exact: tangent planes, wedges at 5 bands), n_phi=32", "transfer",
                "{\"n_phi\": 32, \"bands\": 4, \"transfer\": \"exact\", \"part\": \"transfer\"}",
                kSize, std::nullopt);
  pb::add("part/transfer/n_phi:32/bands:4/transfer:truncated", runs(10, kCaseReps), BM_Transfer,
          false);
  register_case(
      "part/transfer/n_phi:32/bands:4/transfer:truncated",
      "transfer alone (truncated product: wedges + V*C), n_phi=32", "transfer",
      "{\"n_phi\": 32, \"bands\": 4, \"transfer\": \"truncated\", \"part\": \"transfer\"}", kSize,
      std::nullopt);
}

}  // namespace penumbra::terrain_bench
