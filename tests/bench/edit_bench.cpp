// Terrain group, local edit: apply_brush (crater and raise alternately, radius 8 m, so
// 16 x 16 texels) + TerrainShadowing::update_edit on the 256 x 256 field. Goal <= 2 ms.
//
//   edit/16x16    counters: pairs (horizon pairs), texels (transfer texels recomputed) and
//                 edited (texels the brush changed), per iteration
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>

#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

void BM_Edit(benchmark::State& state) {
  constexpr int N = 4;
  auto& shadowing = shadowing_for<N>("edit", ts::TerrainShadowConfig{}, kSize);
  shadowing.update(scene_field(kSize), tbr::kHeightScale);  // the unedited terrain
  const data::HeightField& f0 = shadowing.field();
  ts::Brush brush;
  brush.radius = 8.0f * f0.cell_size;  // 16 x 16 texels
  brush.centre = glm::vec2(0.5f * (f0.width - 1), 0.5f * (f0.height - 1)) * f0.cell_size +
                 glm::vec2(0.5f * f0.cell_size);
  brush.strength = 2.0f;
  std::shared_ptr<const data::HeightField> field = scene_field(kSize);
  double pairs = 0, texels = 0, edited = 0;
  std::int64_t n = 0;
  for (auto _ : state) {
    brush.kind = (n % 2 == 0) ? ts::BrushKind::kCrater : ts::BrushKind::kRaise;
    ts::EditResult e = ts::apply_brush(field, brush);
    const ts::UpdateStats s = shadowing.update_edit(e.field, tbr::kHeightScale, e.changed);
    field = e.field;
    pairs += static_cast<double>(s.horizon_pairs);
    texels += static_cast<double>(s.transfer_texels);
    edited += static_cast<double>(e.changed.count());
    ++n;
  }
  const int n_phi = shadowing.config().azimuths;
  const double per = n > 0 ? 1.0 / static_cast<double>(n) : 0.0;
  set_work(state, texels * per * (n_phi * (kSweepOpsPerPair + wedge_ops(N)) + transfer_ops<N>()),
           texels * per * N * N * 4);
  state.counters["pairs"] = pairs * per;
  state.counters["texels"] = texels * per;
  state.counters["edited"] = edited * per;
  shadowing.update(scene_field(kSize), tbr::kHeightScale);
}

}  // namespace

void register_edit() {
  pb::add("edit/16x16", runs(20, kCaseReps), BM_Edit);
  register_case("edit/16x16", "local edit 16x16 (apply_brush + update_edit)", "sweep",
                "{\"n_phi\": 32, \"bands\": 4, \"brush_radius_cells\": 8}", kSize, 2.0);
}

}  // namespace penumbra::terrain_bench
