// Terrain group, local lights: TerrainShadowing::add_spherical_light on the 256 x 256 field,
// with the irradiance error of the lights alone against the Monte Carlo reference.
//
//   light/cap/{1,4}      the default shading (cap horizon: the horizon towards the light, exact
//                        cap integral), 1 and 4 lights. Goal <= 5 ms per light (thesis: ~16 ms)
//   light/sh_wedges/1    the thesis's SH wedges (16 azimuths), 1 light
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {
namespace {

struct LightDesc {
  glm::vec3 centre;
  float radius;
  glm::vec3 radiance;
};

// Lights 6 m over the terrain at fixed plane positions (fractions of the field).
std::vector<LightDesc> bench_lights(const data::HeightField& f, int count) {
  const glm::vec2 spots[4] = {{0.5f, 0.5f}, {0.25f, 0.25f}, {0.75f, 0.3f}, {0.3f, 0.75f}};
  std::vector<LightDesc> out;
  for (int i = 0; i < count; ++i) {
    const int x = static_cast<int>(spots[i].x * (f.width - 1));
    const int y = static_cast<int>(spots[i].y * (f.height - 1));
    out.push_back({{x * f.cell_size, y * f.cell_size, tbr::kHeightScale * f.at(x, y) + 6.0f},
                   2.0f,
                   {400.0f, 380.0f, 340.0f}});
  }
  return out;
}

// Minimal work of one light (see terrain_bench_common.h).
template <int N>
double light_ops(const ts::TerrainShadowing<N>& s, const LightDesc& l) {
  const data::HeightField& f = s.field();
  const ts::TerrainShadowConfig& c = s.config();
  const int levels = pyramid_levels(std::max(f.width, f.height), c.pyramid.level_step);
  const bool sh_wedges = c.light_shading == ts::LightShading::kShWedges;
  double ops = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::vec3 d = l.centre - s.position(x, y);
      const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
      if (glm::dot(d, d) <= l.radius * l.radius || glm::dot(d, s.normals()[i]) <= -l.radius)
        continue;
      const double dl = std::hypot(d.x, d.y) / f.cell_size;
      const double ray =
          kMarchOpsPerSample * march_samples_to(dl, levels, c.pyramid.level_step) + kAtanOps;
      if (sh_wedges)
        ops += c.light_azimuths * (ray + wedge_ops(N)) + transfer_ops<N>() + 3.0 * N * N;
      else  // the radial sweep: one amortised hull step per texel; else cap_horizons rays
        ops += (c.cap_method == ts::CapHorizons::kRadialSweep ? kSweepOpsPerPair
                                                              : c.cap_horizons * ray) +
               kCapOpsPerStrip * c.cap_strips + kCapSetupOps;
    }
  return ops;
}

// Arg: number of lights. `shading`: the default (cap horizon) or the thesis's SH wedges.
void BM_Lights(benchmark::State& state, ts::LightShading shading, std::string name) {
  constexpr int N = 4;
  const int count = static_cast<int>(state.range(0));
  ts::TerrainShadowConfig config;
  config.light_shading = shading;
  auto& shadowing = shadowing_for<N>(name, config, kSize);
  const auto lights = bench_lights(shadowing.field(), count);
  std::vector<glm::vec3> irradiance(static_cast<std::size_t>(kSize) * kSize);
  for (auto _ : state) {
    std::fill(irradiance.begin(), irradiance.end(), glm::vec3(0.0f));
    for (const LightDesc& l : lights)
      shadowing.add_spherical_light(l.centre, l.radius, l.radiance, irradiance);
    benchmark::DoNotOptimize(irradiance.data());
  }
  double ops = 0;
  for (const LightDesc& l : lights) ops += light_ops<N>(shadowing, l);
  set_work(state, ops, static_cast<double>(kSize) * kSize * 12.0 * count);
  const std::string key = name + "/" + std::to_string(count);
  if (!errors().count(key)) {
    std::vector<tbr::Light> ref;
    for (const LightDesc& l : lights) ref.push_back({l.centre, l.radius, l.radiance});
    errors()[key] = tbr::light_error(kSize, ref, irradiance);
  }
}

}  // namespace

void register_lights() {
  const ts::TerrainShadowConfig defaults;
  const std::string cap_method = std::string("cap_") + ts::to_string(defaults.cap_method);
  const std::string cap_params = "{\"light_shading\": \"cap_horizon\", \"cap_method\": \"" +
                                 std::string(ts::to_string(defaults.cap_method)) +
                                 "\", \"cap_horizons\": " + std::to_string(defaults.cap_horizons) +
                                 ", \"cap_strips\": " + std::to_string(defaults.cap_strips) +
                                 ", \"lights\": ";
  pb::add("light/cap", runs(10, kCaseReps), BM_Lights, ts::LightShading::kCapHorizon,
          std::string("light/cap"))
      ->Arg(1)
      ->Arg(4);
  register_case("light/cap/1", "1 spherical light (default: cap horizon)", cap_method,
                cap_params + "1}", kSize, 5.0);
  register_case("light/cap/4", "4 spherical lights (cap horizon)", cap_method, cap_params + "4}",
                kSize, 20.0);
  pb::add("light/sh_wedges", runs(5, kCaseReps), BM_Lights, ts::LightShading::kShWedges,
          std::string("light/sh_wedges"))
      ->Arg(1);
  register_case("light/sh_wedges/1", "1 spherical light (thesis: SH wedges, 16 azimuths)",
                "sh_wedges_march",
                "{\"light_shading\": \"sh_wedges\", \"light_azimuths\": " +
                    std::to_string(defaults.light_azimuths) +
                    ", \"ls\": 4, \"lo\": 2, \"bands\": 4, \"lights\": 1}",
                kSize, 5.0);
}

}  // namespace penumbra::terrain_bench
