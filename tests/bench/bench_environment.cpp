// The environment benchmark group (issue 15, docs/environment.md "Timing"):
//  - light-source detection (systems/environment, default settings) on sky.exr (512 x 256) and
//    on copies enlarged 2x, 4x and 8x (each texel repeated, up to 4096 x 2048), wall clock;
//  - the OEM build for n = 1, 2, 3 sources at each size (a synthetic sky with three discs,
//    detection done before timing), against 003's way, one projection per OEM: 2^n x the time
//    of one sh::project_equirect<kDefaultBands> of the whole map (measured as BM_Project);
//  - BM_Luminance: the luminance pass alone (eq. 3.1), the detection's O(n) floor;
//  - BM_TerrainKeyLights / BM_BlockerKeyLights: the sources (n = 0..3; the three-source map is
//    studio.exr plus a sun built in code) as key lights of the terrain and of a sphere blocker
//    over a plane against the map's SH alone, time and error against the reference
//    (environment_key_lights.h; --records_out, --chart_out, --chart_n_out).
//
//   build/release/tests/bench/bench_environment --benchmark_out=build/bench/environment_gbench.json
//       --benchmark_out_format=json --summary_out=build/bench/environment_summary.json
//       --records_out=build/bench/environment.json --chart_out=build/bench/environment.svg
//       --chart_n_out=build/bench/environment_n.svg
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <glm/geometric.hpp>

#include "bench_registry.h"
#include "environment_key_lights.h"
#include "penumbra/assets/exr.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/environment/environment_prefilter.h"
#include "penumbra/systems/environment/light_source_detection.h"
#include "penumbra/systems/environment/occluded_environment_maps.h"

namespace pb = penumbra::bench;
namespace env = penumbra::environment;
namespace data = penumbra::data;
namespace sh = penumbra::sh;

namespace {

const std::filesystem::path kSky =
    std::filesystem::path(PENUMBRA_SOURCE_DIR) / ".." / "shared" / "data" / "hdri" / "sky.exr";
constexpr int kScales[] = {1, 2, 4, 8};

// sky.exr with each texel repeated scale x scale times.
const data::EnvironmentMap& sky(int scale) {
  static std::map<int, std::unique_ptr<data::EnvironmentMap>> cache;
  auto& slot = cache[scale];
  if (!slot) {
    static const data::EnvironmentMap base = penumbra::assets::load_environment_map(kSky);
    slot = std::make_unique<data::EnvironmentMap>();
    slot->width = base.width * scale;
    slot->height = base.height * scale;
    slot->source = base.source;
    slot->rgb.resize(static_cast<std::size_t>(slot->width) * slot->height * 3);
    for (int y = 0; y < slot->height; ++y)
      for (int x = 0; x < slot->width; ++x)
        for (int c = 0; c < 3; ++c)
          slot->rgb[3 * (static_cast<std::size_t>(y) * slot->width + x) + c] =
              base.texel(x / scale, y / scale)[c];
  }
  return *slot;
}

// A flat sky with three discs (suns) at the size of sky(scale).
const data::EnvironmentMap& three_suns(int scale) {
  static std::map<int, std::unique_ptr<data::EnvironmentMap>> cache;
  auto& slot = cache[scale];
  if (!slot) {
    slot = std::make_unique<data::EnvironmentMap>();
    slot->width = 512 * scale;
    slot->height = 256 * scale;
    slot->source = "three suns";
    slot->rgb.assign(static_cast<std::size_t>(slot->width) * slot->height * 3, 0.5f);
    const glm::vec3 dirs[3] = {glm::normalize(glm::vec3(1, 1, 1)),
                               glm::normalize(glm::vec3(-1, 0.2f, 0.3f)),
                               glm::normalize(glm::vec3(0.1f, -1, 0.5f))};
    const float values[3] = {3000, 1500, 800};
    for (int y = 0; y < slot->height; ++y)
      for (int x = 0; x < slot->width; ++x) {
        const glm::vec3 d =
            sh::equirect_direction((x + 0.5f) / slot->width, (y + 0.5f) / slot->height);
        for (int k = 0; k < 3; ++k)
          if (glm::dot(d, dirs[k]) > std::cos(0.05f))
            for (int c = 0; c < 3; ++c)
              slot->rgb[3 * (static_cast<std::size_t>(y) * slot->width + x) + c] = values[k];
      }
  }
  return *slot;
}

void BM_Detect(benchmark::State& state) {
  const data::EnvironmentMap& m = sky(static_cast<int>(state.range(0)));
  std::size_t sources = 0;
  for (auto _ : state) {
    const env::LightSourceDetection d = env::detect_light_sources(m);
    sources = d.sources.size();
    benchmark::DoNotOptimize(d.sources.data());
  }
  state.counters["texels"] = static_cast<double>(m.width) * m.height;
  state.counters["sources"] = static_cast<double>(sources);
}

void BM_Luminance(benchmark::State& state) {
  const data::EnvironmentMap& m = sky(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const std::vector<float> l = env::luminance_image(m);
    benchmark::DoNotOptimize(l.data());
  }
}

void BM_Project(benchmark::State& state) {
  const data::EnvironmentMap& m = three_suns(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const auto c = sh::project_equirect<sh::kDefaultBands>(m.rgb.data(), m.width, m.height);
    benchmark::DoNotOptimize(c.data());
  }
}

void BM_OemBuild(benchmark::State& state) {
  const data::EnvironmentMap& m = three_suns(static_cast<int>(state.range(0)));
  env::DetectionSettings s;
  s.source_count = static_cast<int>(state.range(1));
  const env::LightSourceDetection d = env::detect_light_sources(m, s);
  if (static_cast<int>(d.sources.size()) != s.source_count) {
    state.SkipWithError("three_suns: fewer sources than requested");
    return;
  }
  for (auto _ : state) {
    const env::OccludedEnvironmentMaps o = env::build_occluded_environment_maps(m, d);
    benchmark::DoNotOptimize(o.sh.data());
  }
  state.counters["sets"] = static_cast<double>(std::size_t{1} << d.sources.size());
}

void register_benchmarks() {
  using Clock = pb::Timing::Clock;
  const pb::Timing t{
      .clock = Clock::kWall, .unit = benchmark::kMillisecond, .iterations = 3, .repetitions = 3};
  for (int s : kScales) {
    pb::add("BM_Detect", t, BM_Detect)->Arg(s);
    pb::add("BM_Luminance", t, BM_Luminance)->Arg(s);
    pb::add("BM_Project", t, BM_Project)->Arg(s);
    for (int n = 1; n <= 3; ++n) pb::add("BM_OemBuild", t, BM_OemBuild)->Args({s, n});
  }
}

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  for (int k : kScales) {
    const std::string size = std::to_string(512 * k) + "x" + std::to_string(256 * k);
    const std::string a = "/" + std::to_string(k);
    const auto detect = pb::scale(r.real_ns("BM_Detect" + a), 1e-6);
    const auto lum = pb::scale(r.real_ns("BM_Luminance" + a), 1e-6);
    s.add_vs_baseline("sky.exr " + size + ": detection", "ms", detect, std::nullopt,
                      pb::Goal::none(), lum, "default settings; floor: the luminance pass alone");
    const auto project = pb::scale(r.real_ns("BM_Project" + a), 1e-6);
    for (int n = 1; n <= 3; ++n) {
      const auto oem = pb::scale(r.real_ns("BM_OemBuild" + a + "/" + std::to_string(n)), 1e-6);
      s.add_vs_baseline(
          size + ": OEM build, n = " + std::to_string(n) + " (" + std::to_string(1 << n) + " sets)",
          "ms", oem, pb::scale(project, static_cast<double>(1 << n)), pb::Goal::none(), project,
          "baseline: 003's one projection per OEM; floor: one projection");
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string records = pb::take_flag(argc, argv, "records_out");
  const std::string chart = pb::take_flag(argc, argv, "chart_out");
  const std::string chart_n = pb::take_flag(argc, argv, "chart_n_out");
  return pb::run_group(
      argc, argv, "environment",
      [] {
        register_benchmarks();
        pb::environment_keys::register_benchmarks();
      },
      [&](const pb::Results& r) {
        pb::Summary s = summarize(r);
        pb::environment_keys::summarize(r, s);
        pb::environment_keys::write_outputs(r, records, chart, chart_n);
        return s;
      });
}
