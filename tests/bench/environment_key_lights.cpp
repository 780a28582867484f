#include "environment_key_lights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "../environment/three_source_map.h"
#include "bench_chart.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/environment/environment_light_update.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "terrain_reference.h"

namespace penumbra::bench::environment_keys {
namespace {

namespace tr = terrain_reference;
constexpr int kN = sh::kDefaultBands;
constexpr float kRotation = 0.7f;  // as the terrain accuracy tests
// "sphere": one sphere blocker over a plane (BlockerAccumulation); the others are terrains.
const char* const kScenes[] = {"dem", "mountains", "sphere"};
// studio_sun: studio.exr plus a sun (three_source_map.h), the one map with three sources.
const char* const kMaps[] = {"sky", "sunset", "sunrise", "studio", "studio_sun"};
// Key lights registered per map (studio_sun has three sources; the others are skipped above what
// the detection finds).
int max_keys(const std::string& map) {
  return map == "studio_sun" ? 3 : 2;
}
bool terrain(const std::string& scene) {
  return scene != "sphere";
}

const data::EnvironmentMap& load_map(const std::string& map) {
  static std::map<std::string, std::unique_ptr<const data::EnvironmentMap>> maps;
  auto& m = maps[map];
  if (!m)
    m = std::make_unique<const data::EnvironmentMap>(
        map == "studio_sun" ? test::three_sources::add_sun(tr::load_hdri("studio"))
                            : tr::load_hdri(map));
  return *m;
}

// The map's sources (three requested) and OEMs, detected once per map.
const components::EnvironmentLight& environment_of(const std::string& map) {
  static std::map<std::string, std::unique_ptr<components::EnvironmentLight>> cache;
  auto& slot = cache[map];
  if (!slot) {
    slot = std::make_unique<components::EnvironmentLight>();
    slot->map = std::make_shared<const data::EnvironmentMap>(load_map(map));
    environment::DetectionSettings ds;
    ds.source_count = 3;
    environment::update_environment_light(*slot, ds);
    slot->radiance = slot->oem_sh.back();  // the whole map's SH (every source in it)
  }
  return *slot;
}

// A terrain under a map: the system, the detected sources and OEMs, the reference.
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
    slot->env = environment_of(map);
    const data::EnvironmentMap* m = slot->env.map.get();
    slot->field = tr::load_terrain(scene, 256);
    slot->ts = std::make_unique<terrain_shadow::TerrainShadowing<kN>>();
    slot->ts->update(slot->field, 1.0f);
    tr::Lighting lighting;
    lighting.environment = m;
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

// One sphere (radius 1 m, centre 2 m up) over a plane, receivers on the plane every 0.5 m over
// 8 m x 8 m (17 x 17, normal +z), the map unrotated: the blocker accuracy test's scene
// (tests/blocker_accumulation) with a grid instead of a line, so that every source's shadow
// crosses receivers.
struct SphereCase {
  components::EnvironmentLight env;
  blocker_accumulation::BlockerAccumulation<kN> acc;
  std::vector<reference::Receiver> receivers;
  std::vector<reference::RgbEstimate> ref;
};

SphereCase& get_sphere(const std::string& map) {
  static std::map<std::string, std::unique_ptr<SphereCase>> cache;
  auto& slot = cache[map];
  if (!slot) {
    slot = std::make_unique<SphereCase>();
    slot->env = environment_of(map);
    const std::vector<blocker_accumulation::WorldSphere> one = {{{0, 0, 2}, 1}};
    slot->acc.set_blockers(one);
    for (int j = 0; j <= 16; ++j)
      for (int i = 0; i <= 16; ++i)
        slot->receivers.push_back({{-4.0f + 0.5f * i, -4.0f + 0.5f * j, 0.0f}, {0, 0, 1}});
    reference::SceneDesc desc;
    desc.environment = reference::EnvironmentLight{*slot->env.map, 0.0f};
    desc.spheres.push_back({one[0].centre, one[0].radius, ""});
    reference::IrradianceOptions o;
    o.samples = 4096;
    slot->ref = reference::environment_irradiance(reference::Scene(desc), slot->receivers, o);
  }
  return *slot;
}

// Every receiver shaded with the first n sources as key lights: the OEM without them through
// the blockers' SH visibility, plus each source's irradiance x cos x the share of its disc the
// sphere leaves ([Ambrosj16] ch. 4; BlockerAccumulation::key_light_visibility).
std::vector<glm::vec3> shade_sphere(const SphereCase& c, int n) {
  const auto& rest = components::sh_without(c.env, (std::size_t{1} << n) - 1);
  std::vector<glm::vec3> e(c.receivers.size());
  for (std::size_t i = 0; i < e.size(); ++i) {
    const glm::vec3 p = c.receivers[i].position, nrm = c.receivers[i].normal;
    e[i] = c.acc.irradiance(rest, p, nrm);
    for (int j = 0; j < n; ++j) {
      const components::EnvironmentSource& s = c.env.sources[static_cast<std::size_t>(j)];
      const float cos = glm::dot(nrm, s.direction);
      if (cos > 0)
        e[i] += s.irradiance * cos * c.acc.key_light_visibility(p, s.direction, s.angular_radius);
    }
  }
  return e;
}

// The counters every key-light case reports: its error against the reference, and how many
// sources were found and taken out.
void count_errors(benchmark::State& state, const tr::ErrorSummary& err, std::size_t sources,
                  int n) {
  state.counters["rel_rms_vs_reference"] = err.rel_rms;
  state.counters["max_rel_vs_reference"] = err.max_rel;
  state.counters["reference_rel_se"] = err.ref_rel_se;
  state.counters["bias_vs_reference"] = err.bias;
  state.counters["sources_found"] = static_cast<double>(sources);
  state.counters["key_lights"] = n;
}

void BM_BlockerKeyLights(benchmark::State& state, std::string map, int n) {
  SphereCase& c = get_sphere(map);
  if (n > static_cast<int>(c.env.sources.size())) {
    state.SkipWithError("fewer sources found");
    return;
  }
  std::vector<glm::vec3> e;
  for (auto _ : state) {
    e = shade_sphere(c, n);
    benchmark::DoNotOptimize(e.data());
  }
  std::vector<std::size_t> all(e.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const tr::ErrorSummary err = tr::compare(e, all, c.ref);
  count_errors(state, err, c.env.sources.size(), n);
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
  count_errors(state, err, c.env.sources.size(), n);
}

std::string key(const std::string& scene, const std::string& map, int n) {
  return (terrain(scene) ? "BM_TerrainKeyLights/" + scene + "/"
                         : std::string("BM_BlockerKeyLights/")) +
         map + "/n:" + std::to_string(n);
}

std::string map_file(const std::string& map) {
  return map == "studio_sun" ? std::string("studio.exr + sun") : map + ".exr";
}

// The chart of error against the number of key lights, one line per scene and map.
// ref_se_percent: the smallest and largest relative standard error of the references.
void write_n_chart(const std::vector<LineSeries>& lines, const double ref_se_percent[2],
                   const std::string& path) {
  if (path.empty()) return;
  LineChartSpec spec;
  spec.title = "Environment sources as key lights: error against n";
  spec.subtitle =
      "256^2 terrains (32 x 32 texel receivers) and a sphere over a plane (17 x 17) vs the "
      "reference integrator; n = 0: the map's SH alone";
  spec.x_label =
      "n: the map's brightest sources taken out of the SH as key lights ([Ambrosj16] ch. 4)";
  spec.y_label = "relative RMS irradiance error vs reference, %";
  spec.x_min = 0;
  spec.x_max = 3;
  spec.legend_title = "scene, map";
  std::ostringstream noise;
  noise.precision(2);
  noise << "reference noise " << ref_se_percent[0] << "-" << ref_se_percent[1] << "%";
  spec.notes = {"colour: map; line: scene", "(solid dem, dashed mountains,", "dotted sphere)",
                "n stops at the sources found", noise.str()};
  spec.empty_text = "no key-light case with a reference error in this run";
  if (!write_atomically(path, line_chart_svg(spec, lines)))
    std::fprintf(stderr, "bench_environment: cannot write %s\n", path.c_str());
}

}  // namespace

void register_benchmarks() {
  const Timing t{.clock = Timing::Clock::kWall, .unit = benchmark::kMillisecond};
  for (const char* scene : kScenes)
    for (const char* map : kMaps)
      for (int n = 0; n <= max_keys(map); ++n) {  // skipped where fewer sources are found
        if (terrain(scene))
          add(key(scene, map, n), t, BM_TerrainKeyLights, std::string(scene), std::string(map), n);
        else
          add(key(scene, map, n), t, BM_BlockerKeyLights, std::string(map), n);
      }
}

void summarize(const Results& r, Summary& s) {
  for (const char* scene : kScenes)
    for (const char* map : kMaps) {
      const auto base = scale(r.real_ns(key(scene, map, 0)), 1e-6);
      for (int n = 0; n <= max_keys(map); ++n) {
        const auto ms = scale(r.real_ns(key(scene, map, n)), 1e-6);
        if (!ms) continue;  // fewer sources found
        const auto e = r.counter(key(scene, map, n), "rel_rms_vs_reference");
        const auto mx = r.counter(key(scene, map, n), "max_rel_vs_reference");
        const auto se = r.counter(key(scene, map, n), "reference_rel_se");
        std::ostringstream note;
        note << "rel. RMS vs reference ";
        if (e)
          note << std::round(*e * 10000) / 100 << "%";
        else
          note << "-";
        if (mx) note << ", max " << std::round(*mx * 1000) / 10 << "%";
        if (se) note << " (reference noise " << std::round(*se * 10000) / 100 << "%)";
        const std::string what =
            terrain(scene)
                ? std::string("terrain ") + scene + " 256^2, " + map_file(map) + ": compose"
                : "sphere over a plane, " + map_file(map) + ": 289 receivers";
        s.add_vs_baseline(what + ", n = " + std::to_string(n), "ms", ms, base, Goal::none(),
                          std::nullopt, note.str() + "; baseline: n = 0 (the map's SH alone)");
      }
    }
}

void write_outputs(const Results& r, const std::string& records_path, const std::string& chart_path,
                   const std::string& chart_n_path) {
  std::vector<ChartPoint> points;
  std::vector<LineSeries> lines;  // one per scene and map: error against n
  double ref_se_percent[2] = {1e300, 0};
  std::ostringstream o;
  double load[3] = {0, 0, 0};
  const int nl = getloadavg(load, 3);
  o << "{\n  \"format\": \"penumbra-environment-key-lights\",\n  \"version\": 2,\n"
    << "  \"cpus\": " << std::thread::hardware_concurrency() << ",\n  \"load_avg_at_end\": ["
    << (nl > 0 ? load[0] : 0) << ", " << (nl > 1 ? load[1] : 0) << ", " << (nl > 2 ? load[2] : 0)
    << "],\n  \"records\": [";
  bool first = true;
  for (int si = 0; si < static_cast<int>(std::size(kScenes)); ++si)
    for (int mi = 0; mi < static_cast<int>(std::size(kMaps)); ++mi) {
      const char* scene = kScenes[si];
      const char* map = kMaps[mi];
      LineSeries line{.name = std::string(scene) + ", " + map_file(map),
                      .x = {},
                      .y = {},
                      .colour = mi,
                      .dash = si};
      for (int n = 0; n <= max_keys(map); ++n) {
        const std::string k = key(scene, map, n);
        const auto ms = scale(r.real_ns(k), 1e-6);
        const auto e = r.counter(k, "rel_rms_vs_reference");
        const auto mx = r.counter(k, "max_rel_vs_reference");
        const auto se = r.counter(k, "reference_rel_se");
        const auto bias = r.counter(k, "bias_vs_reference");
        if (!ms || !e) continue;
        o << (first ? "\n" : ",\n") << "    {\"key\": \"" << k << "\", \"scene\": \"" << scene
          << "\", \"map\": \"" << map << "\", \"key_lights\": " << n << ", \"ms\": " << *ms
          << ", \"rel_rms_error\": " << *e << ", \"max_rel_error\": " << mx.value_or(0)
          << ", \"bias\": " << bias.value_or(0) << ", \"reference_rel_se\": " << se.value_or(0)
          << "}";
        first = false;
        points.push_back({.ms = *ms,
                          .error_percent = *e * 100,
                          .series = map_file(map),
                          .label = std::string(scene) + " n=" + std::to_string(n),
                          .key = k,
                          .front = std::string(scene) + "/" + map});
        line.x.push_back(n);
        line.y.push_back(*e * 100);
        if (se) {
          ref_se_percent[0] = std::min(ref_se_percent[0], *se * 100);
          ref_se_percent[1] = std::max(ref_se_percent[1], *se * 100);
        }
      }
      if (!line.x.empty()) lines.push_back(std::move(line));
    }
  o << "\n  ]\n}\n";
  if (!records_path.empty() && !write_atomically(records_path, o.str()))
    std::fprintf(stderr, "bench_environment: cannot write %s\n", records_path.c_str());
  if (ref_se_percent[0] > ref_se_percent[1]) ref_se_percent[0] = ref_se_percent[1] = 0;
  write_n_chart(lines, ref_se_percent, chart_n_path);
  if (chart_path.empty()) return;
  ChartSpec spec;
  spec.title = "Environment sources as key lights: error against time, n = 0..3";
  spec.subtitle =
      "256^2 terrains (32 x 32 texel receivers) and a sphere over a plane (17 x 17) vs the "
      "reference integrator; n = key lights ([Ambrosj16] ch. 4), n = 0: the map's SH alone";
  spec.x_label =
      "one frame: terrain compose (SH + key-light sweeps) or the sphere scene's receivers, ms "
      "(log)";
  spec.y_label = "relative RMS irradiance error vs reference, %";
  spec.legend_title = "map";
  spec.front_note = "dashed grey: Pareto front per scene and map";
  spec.best_note = "";
  if (!write_atomically(chart_path, chart_svg(spec, points)))
    std::fprintf(stderr, "bench_environment: cannot write %s\n", chart_path.c_str());
}

}  // namespace penumbra::bench::environment_keys
