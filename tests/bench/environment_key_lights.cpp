#include "environment_key_lights.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "bench_chart.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/environment/environment_light_update.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "terrain_reference.h"

namespace penumbra::bench::environment_keys {
namespace {

namespace tr = terrain_reference;
constexpr int kN = sh::kDefaultBands;
constexpr float kRotation = 0.7f;  // as the terrain accuracy tests
const char* const kScenes[] = {"dem", "mountains"};
const char* const kMaps[] = {"sky", "sunset", "sunrise", "studio"};
constexpr int kMaxKeys = 2;  // studio.exr has two sources under the radius limit

// A scene under a map: the system, the detected sources and OEMs, the reference.
struct Case {
  std::shared_ptr<const data::HeightField> field;
  std::unique_ptr<terrain_shadow::TerrainShadowing<kN>> ts;
  components::EnvironmentLight env;
  tr::ReferenceIrradiance ref;
};

Case& get(const std::string& scene, const std::string& map) {
  static std::map<std::string, std::unique_ptr<Case>> cache;
  auto& slot = cache[scene + "/" + map];
  if (!slot) {
    slot = std::make_unique<Case>();
    static std::map<std::string, std::shared_ptr<const data::EnvironmentMap>> maps;
    auto& m = maps[map];
    if (!m) m = std::make_shared<const data::EnvironmentMap>(tr::load_hdri(map));
    slot->env.map = m;
    environment::DetectionSettings ds;
    ds.source_count = 3;
    environment::update_environment_light(slot->env, ds);
    slot->env.radiance = slot->env.oem_sh.back();  // the whole map's SH (every source in it)
    slot->field = tr::load_terrain(scene, 256);
    slot->ts = std::make_unique<terrain_shadow::TerrainShadowing<kN>>();
    slot->ts->update(slot->field, 1.0f);
    tr::Lighting lighting;
    lighting.environment = m.get();
    lighting.rotation_z = kRotation;
    slot->ref = tr::reference_irradiance(*slot->field, 1.0f,
                                         tr::texel_receivers(*slot->field, 1.0f, 8), lighting);
  }
  return *slot;
}

// One frame's compose with the first n sources as key lights (n = 0: the whole map's SH).
std::vector<glm::vec3> compose(const Case& c, int n) {
  const auto& rest = components::sh_without(c.env, (std::size_t{1} << n) - 1);
  sh::CoeffsRgb<kN> radiance{};
  for (int ch = 0; ch < 3; ++ch) radiance[ch] = sh::rotate_z<kN>(rest[ch], kRotation);
  std::vector<glm::vec3> e;
  c.ts->shade_environment(radiance, e);  // [Meier13] eq. 4.21
  std::vector<float> horizons;
  for (int j = 0; j < n; ++j) {  // [Ambrosj16] ch. 4: each source a key light
    const components::EnvironmentSource& s = c.env.sources[static_cast<std::size_t>(j)];
    const glm::vec3 d = components::world_direction(s, kRotation);
    c.ts->key_light_horizons(d, horizons);
    c.ts->add_key_light(d, s.angular_radius, s.irradiance, horizons, e);
  }
  return e;
}

void BM_TerrainKeyLights(benchmark::State& state, std::string scene, std::string map, int n) {
  Case& c = get(scene, map);
  if (n > static_cast<int>(c.env.sources.size())) {
    state.SkipWithError("fewer sources found");
    return;
  }
  std::vector<glm::vec3> e;
  for (auto _ : state) {
    e = compose(c, n);
    benchmark::DoNotOptimize(e.data());
  }
  const tr::ErrorSummary err = tr::compare(e, c.ref.texels, c.ref.environment);
  state.counters["rel_rms_vs_reference"] = err.rel_rms;
  state.counters["max_rel_vs_reference"] = err.max_rel;
  state.counters["reference_rel_se"] = err.ref_rel_se;
  state.counters["sources_found"] = static_cast<double>(c.env.sources.size());
  state.counters["key_lights"] = n;
}

std::string key(const std::string& scene, const std::string& map, int n) {
  return "BM_TerrainKeyLights/" + scene + "/" + map + "/n:" + std::to_string(n);
}

}  // namespace

void register_benchmarks() {
  const Timing t{.clock = Timing::Clock::kWall, .unit = benchmark::kMillisecond};
  for (const char* scene : kScenes)
    for (const char* map : kMaps)
      for (int n = 0; n <= kMaxKeys; ++n)  // skipped where fewer sources are found
        add(key(scene, map, n), t, BM_TerrainKeyLights, std::string(scene), std::string(map), n);
}

void summarize(const Results& r, Summary& s) {
  for (const char* scene : kScenes)
    for (const char* map : kMaps) {
      const auto base = scale(r.real_ns(key(scene, map, 0)), 1e-6);
      for (int n = 0; n <= kMaxKeys; ++n) {
        const auto ms = scale(r.real_ns(key(scene, map, n)), 1e-6);
        if (!ms) continue;  // fewer sources found
        const auto e = r.counter(key(scene, map, n), "rel_rms_vs_reference");
        std::ostringstream note;
        note << "rel. RMS vs reference ";
        if (e)
          note << std::round(*e * 10000) / 100 << "%";
        else
          note << "-";
        s.add_vs_baseline(std::string("terrain ") + scene + " 256^2, " + map +
                              ".exr: compose, n = " + std::to_string(n),
                          "ms", ms, base, Goal::none(), std::nullopt,
                          note.str() + "; baseline: n = 0 (the map's SH alone)");
      }
    }
}

void write_outputs(const Results& r, const std::string& records_path,
                   const std::string& chart_path) {
  std::vector<ChartPoint> points;
  std::ostringstream o;
  double load[3] = {0, 0, 0};
  const int nl = getloadavg(load, 3);
  o << "{\n  \"format\": \"penumbra-environment-key-lights\",\n  \"version\": 1,\n"
    << "  \"cpus\": " << std::thread::hardware_concurrency() << ",\n  \"load_avg_at_end\": ["
    << (nl > 0 ? load[0] : 0) << ", " << (nl > 1 ? load[1] : 0) << ", " << (nl > 2 ? load[2] : 0)
    << "],\n  \"records\": [";
  bool first = true;
  for (const char* scene : kScenes)
    for (const char* map : kMaps)
      for (int n = 0; n <= kMaxKeys; ++n) {
        const std::string k = key(scene, map, n);
        const auto ms = scale(r.real_ns(k), 1e-6);
        const auto e = r.counter(k, "rel_rms_vs_reference");
        const auto mx = r.counter(k, "max_rel_vs_reference");
        const auto se = r.counter(k, "reference_rel_se");
        if (!ms || !e) continue;
        o << (first ? "\n" : ",\n") << "    {\"key\": \"" << k << "\", \"scene\": \"" << scene
          << "\", \"map\": \"" << map << "\", \"key_lights\": " << n << ", \"ms\": " << *ms
          << ", \"rel_rms_error\": " << *e << ", \"max_rel_error\": " << mx.value_or(0)
          << ", \"reference_rel_se\": " << se.value_or(0) << "}";
        first = false;
        points.push_back({.ms = *ms,
                          .error_percent = *e * 100,
                          .series = std::string(map) + ".exr",
                          .label = std::string(scene) + " n=" + std::to_string(n),
                          .key = k,
                          .front = map});
      }
  o << "\n  ]\n}\n";
  if (!records_path.empty() && !write_atomically(records_path, o.str()))
    std::fprintf(stderr, "bench_environment: cannot write %s\n", records_path.c_str());
  if (chart_path.empty()) return;
  ChartSpec spec;
  spec.title = "Environment sources as the terrain's key lights: error against compose time";
  spec.subtitle =
      "256^2 terrains, 32 x 32 texel receivers vs the reference integrator (full-resolution map); "
      "n = key lights ([Ambrosj16] ch. 4), n = 0: the map's SH alone";
  spec.x_label = "compose of one frame (SH shading + key-light sweeps and shading), ms (log)";
  spec.y_label = "relative RMS irradiance error vs reference, %";
  spec.legend_title = "map";
  spec.front_note = "dashed grey: Pareto front per map";
  spec.best_note = "";
  if (!write_atomically(chart_path, chart_svg(spec, points)))
    std::fprintf(stderr, "bench_environment: cannot write %s\n", chart_path.c_str());
}

}  // namespace penumbra::bench::environment_keys
