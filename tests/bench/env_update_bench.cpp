// Terrain group, the full environment update: TerrainShadowing::update() (normals, pyramid for
// the march only, horizons, transfer), timed per configuration, with its irradiance error against
// the Monte Carlo reference computed once outside the timed loop.
//
//   env/{sweep,march,brute_force}/256/...   the main cases (goal <= 10 ms; brute force: 1 run)
//   env/sweep/1024/n_phi:64/bands:4         the large field (Timonen and Westerholm 2010)
//   sweep/...                               speed versus accuracy, one point per configuration
#include <sstream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "terrain_bench_common.h"

namespace penumbra::terrain_bench {

ts::TerrainShadowConfig EnvConfig::config() const {
  ts::TerrainShadowConfig c;
  c.method = method == "sweep"   ? ts::HorizonMethod::kSweep
             : method == "march" ? ts::HorizonMethod::kMarch
                                 : ts::HorizonMethod::kBruteForce;
  c.azimuths = n_phi;
  c.pyramid.level_step = ls;
  c.march.level_offset = lo;
  c.transfer =
      transfer == "truncated" ? ts::TransferMethod::kTruncatedProduct : ts::TransferMethod::kExact;
  return c;
}

std::string EnvConfig::params_text() const {
  std::string s = "n_phi:" + std::to_string(n_phi);
  if (uses_march_params())
    s += "/ls:" + std::to_string(ls) + "/lo:" + std::to_string(static_cast<int>(lo));
  s += "/bands:" + std::to_string(bands);
  return transfer == "exact" ? s : s + "/transfer:" + transfer;
}

std::string EnvConfig::params_json() const {
  std::ostringstream o;
  o << "{\"n_phi\": " << n_phi;
  if (uses_march_params()) o << ", \"ls\": " << ls << ", \"lo\": " << lo;
  o << ", \"bands\": " << bands << ", \"transfer\": \"" << transfer << "\"}";
  return o.str();
}

double EnvConfig::ops() const {
  const double texels = static_cast<double>(size) * size;
  const int levels = pyramid_levels(size, ls);
  double horizon = 0;
  if (method == "sweep") {
    horizon = kSweepOpsPerPair;
  } else if (method == "march") {
    horizon = kMarchOpsPerSample * march_samples_all(levels) + kAtanOps;
  } else {  // brute force: the texel's whole ray, about size / 2 samples on average
    horizon = (3.0 + 1.0) * size / 2 + kAtanOps;
  }
  // The pyramid is built only for the march (the default lights sweep: cap_method kRadialSweep).
  const double pyramid = method == "march" ? texels * levels * kPyramidOpsPerSample : 0.0;
  const double transfer_part = transfer == "exact" ? exact_transfer_ops(bands, n_phi)
                                                   : n_phi * wedge_ops(bands) + transfer_ops(bands);
  return texels * (n_phi * horizon + transfer_part) + pyramid;
}

double EnvConfig::bytes() const {
  return static_cast<double>(size) * size * 4.0 * (1 + bands * bands);
}

namespace {

template <int N>
void env_update(benchmark::State& state, const EnvConfig& cfg, bool with_error,
                const std::string& key) {
  auto& shadowing = shadowing_for<N>(key, cfg.config(), cfg.size);
  const auto field = scene_field(cfg.size);
  for (auto _ : state) {
    shadowing.update(field, tbr::kHeightScale);
    benchmark::DoNotOptimize(shadowing.transfer().data());
  }
  set_work(state, cfg.ops(), cfg.bytes());
  if (with_error && !errors().count(key)) {
    std::vector<glm::vec3> irradiance;
    shadowing.shade_environment(environment_sh<N>(), irradiance);
    errors()[key] = tbr::environment_error(cfg.size, irradiance);
  }
}

void BM_EnvUpdate(benchmark::State& state, EnvConfig cfg, bool with_error, std::string key) {
  switch (cfg.bands) {
    case 3:
      env_update<3>(state, cfg, with_error, key);
      break;
    case 5:
      env_update<5>(state, cfg, with_error, key);
      break;
    case 6:
      env_update<6>(state, cfg, with_error, key);
      break;
    default:
      env_update<4>(state, cfg, with_error, key);
  }
}

// kind: "case" (a main case, named env/...) or "sweep" (a speed-versus-accuracy point, sweep/...).
void register_env(const EnvConfig& cfg, const std::string& kind, int iterations, int repetitions,
                  std::optional<double> goal, bool with_error) {
  const std::string name = (kind == "sweep" ? "sweep/" : "env/") + cfg.method + "/" +
                           std::to_string(cfg.size) + "/" + cfg.params_text();
  pb::add(name, runs(iterations, repetitions), BM_EnvUpdate, cfg, with_error, name);
  CaseInfo c;
  c.key = name;
  c.title = "env update " + std::to_string(cfg.size) + "^2 " + cfg.method + " " + cfg.params_text();
  c.kind = kind;
  c.method = cfg.method;
  c.params_json = cfg.params_json();
  c.size = cfg.size;
  c.goal_ms = goal;
  c.env = cfg;
  c.is_env = true;
  cases().push_back(c);
}

}  // namespace

void register_env_cases() {
  EnvConfig sweep32;
  register_env(sweep32, "case", 10, kCaseReps, 10.0, true);
  EnvConfig march;
  march.method = "march";
  register_env(march, "case", 5, kCaseReps, 10.0, true);
  EnvConfig brute;
  brute.method = "brute_force";
  register_env(brute, "case", 1, 1, std::nullopt, true);
}

void register_env_big() {
  EnvConfig big;
  big.size = kBigSize;
  big.n_phi = 64;
  register_env(big, "case", 1, 3, std::nullopt, false);
}

// Speed versus accuracy: one point per method and parameter set.
void register_env_sweep() {
  for (int n_phi : {4, 8, 16, 32, 64}) {
    EnvConfig c;
    c.n_phi = n_phi;
    register_env(c, "sweep", 3, 5, std::nullopt, true);
  }
  for (int n_phi : {4, 8, 16, 64}) {
    EnvConfig c;
    c.method = "march";
    c.n_phi = n_phi;
    register_env(c, "sweep", 3, 5, std::nullopt, true);
  }
  for (float lo : {0.0f, 2.0f})
    for (int ls : {1, 2, 3, 4}) {
      EnvConfig c;
      c.method = "march";
      c.ls = ls;
      c.lo = lo;
      register_env(c, "sweep", 3, 5, std::nullopt, true);
    }
  // Band counts 3-6 (issue 20): the exact transfer (default; 4 bands are the points above) and
  // the thesis's truncated product beside it.
  for (int n_phi : {8, 32})
    for (const char* transfer : {"exact", "truncated"})
      for (int bands : {3, 4, 5, 6}) {
        EnvConfig c;
        c.n_phi = n_phi;
        c.bands = bands;
        c.transfer = transfer;
        if (c.transfer == "exact" && bands == 4) continue;
        register_env(c, "sweep", 3, 5, std::nullopt, true);
      }
}

}  // namespace penumbra::terrain_bench
