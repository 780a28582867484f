// Benchmark group "terrain": speed and accuracy of the terrain shadow system
// (systems/terrain_shadow, [Meier13] ch. 4-6) on this machine's 2 threads.
//
//   build/release/tests/bench/bench_terrain [--benchmark_* flags] [--summary_out=PATH]
//       [--records_out=PATH.json] [--chart_out=PATH.svg]
//
// Cases (256 x 256 "mountains" unless said otherwise, 4 SH bands, median over repetitions):
//  - env/...       TerrainShadowing::update(): normals, pyramid (march only: the default lights
//                  sweep), horizons, transfer. Sweep (default, n_phi = 32), march (ls 4, lo 2),
//                  brute force (1 iteration). Goal <= 10 ms (thesis table 6.6 on a GTX 560:
//                  1.7 ms pyramid + 6.7 ms environment pass).
//  - part/...      the breakdown: pyramid alone, horizons alone (sweep, march), transfer alone.
//  - light/...     add_spherical_light, 1 and 4 lights with the default shading (cap horizon:
//                  the horizon towards the light, exact cap integral), 1 light with the
//                  thesis's SH wedges (16 azimuths). Goal <= 5 ms per light (thesis: ~16 ms).
//  - edit/16x16    apply_brush (crater/raise alternately, radius 8 m) + update_edit. Goal <= 2 ms.
//  - env/1024      1024 x 1024, 64 azimuths, sweep (Timonen and Westerholm 2010: ~43 ms a
//                  frame on a GTX 280).
//  - shade         rotating environment: rotate_z of the SH radiance + shade_environment from
//                  the stored transfer.
//  - sweep/...     speed versus accuracy: one full update per configuration (n_phi, ls/lo,
//                  bands), few iterations, with its irradiance error against the Monte Carlo
//                  reference (rel_rms, max_rel at subsampled receivers, one HDR map).
//
// Floors: the minimal arithmetic of each case (lane operations counted below, an FMA = 1) at
// the vector peak measured in this run (AVX2 FMA chains on both threads), or its minimal
// memory traffic at the streaming-read bandwidth measured in this run (L3-sized buffer when the
// case's data fit in the 32 MiB L3, else a DRAM-sized one), whichever is larger. Counts:
//   sweep horizon:   16 per (texel, azimuth): interpolated sample 1, hull test 3, slope 1,
//                    arctangent 10, blend onto the texel 1 (amortised O(1) per sample)
//   march horizon:   8 per sample (bilinear 3, slope 1, spline maximum 4) + 10 per (texel,
//                    azimuth) for one arctangent
//   wedge (eq. 4.19): 5 N^2 per (texel, azimuth): bilinear table lookup 3 N^2, z rotation and
//                    accumulation 2 N^2
//   transfer (4.21): 2 N^2 (rotate the clamped cosine to n) + the factored product's FMAs
//   shading:         3 N^2 per texel (one dot per channel)
//   pyramid:         6 per sample and level (height_pyramid.h)
//   lights:          for the texels the light is not culled for: march samples up to the light
//                    as above per horizon direction; SH wedges: 16 azimuths, sphere wedges
//                    5 N^2 each, transfer, cap radiance 2 N^2 and dot N^2; cap horizon:
//                    16 for the radial sweep's hull step (cap_method kRadialSweep, else
//                    cap_horizons march rays), 10 per chord (cap_strips) + 20 set-up
//   edit:            the texels whose horizons or normal changed (UpdateStats::transfer_texels)
//                    times (n_phi sweep pairs + wedges + transfer)
//
// --records_out writes one JSON record per measured case and per sweep point (scene, method,
// params, size, ms, floor_ms, rel_rms_error, max_rel_error); --chart_out the speed-versus-
// accuracy chart as SVG. Both written atomically (temporary file, then rename).
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "bench_report.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"
#include "terrain_bench_reference.h"

namespace {

namespace pb = penumbra::bench;
namespace ts = penumbra::terrain_shadow;
namespace data = penumbra::data;
namespace sh = penumbra::sh;
namespace tbr = penumbra::bench::terrain;

constexpr int kSize = 256;
constexpr int kCaseReps = 9;  // repetitions of the main cases (the median is reported)
constexpr int kBigSize = 1024;
constexpr double kL3Bytes = 32.0 * 1024 * 1024;

// ---------------------------------------------------------------------------------------------
// Op counts (see the header)

constexpr double kSweepOpsPerPair = 16;
constexpr double kMarchOpsPerSample = 8;
constexpr double kAtanOps = 10;
constexpr double kPyramidOpsPerSample = 6;
constexpr double kCapOpsPerStrip = 10;
constexpr double kCapSetupOps = 20;

double wedge_ops(int n) {
  return 5.0 * n * n;
}
template <int N>
double transfer_ops() {
  return 2.0 * N * N + sh::factored_term_count<N>();
}
double transfer_ops(int n) {
  return n == 3 ? transfer_ops<3>() : n == 4 ? transfer_ops<4>() : transfer_ops<5>();
}

// Samples of the march (d_0 = 1, d_{i+1} = d_i + sr^i, `levels` of them) used for a light at
// plane distance `dl` cells: up to and including the first beyond it (horizon_march.cpp).
int march_samples_to(double dl, int levels, int level_step) {
  const double sr = std::exp2(1.0 / level_step);
  double d = 1, spacing = 1;
  int k = 0;
  for (int i = 0; i < levels; ++i, d += spacing, spacing *= sr)
    if (d <= dl) ++k;
  return std::min(k, levels - 1) + 1;
}
int march_samples_all(int levels) {
  return levels;
}

int pyramid_levels(int size, int level_step) {
  return static_cast<int>(std::ceil(level_step * std::log2(static_cast<double>(size)) - 1e-9)) + 1;
}

// Per-iteration work of a case, reported as counters so the summary can turn it into a floor.
void set_work(benchmark::State& state, double ops, double bytes) {
  state.counters["ops"] = ops;
  state.counters["bytes"] = bytes;
}

// ---------------------------------------------------------------------------------------------
// Scenes and environment

std::shared_ptr<const data::HeightField> scene_field(int size) {
  static std::map<int, std::shared_ptr<const data::HeightField>> cache;
  auto& f = cache[size];
  if (!f) f = tbr::load_scene(tbr::kSceneName, size);
  return f;
}

template <int N>
const sh::CoeffsRgb<N>& environment_sh() {
  static const sh::CoeffsRgb<N> radiance = tbr::environment_sh<N>();
  return radiance;
}

// ---------------------------------------------------------------------------------------------
// Same-run machine baselines: vector peak and streaming-read bandwidth on both threads

constexpr int kPeakChunks = 64;
constexpr int kPeakReps = 16384;
constexpr int kPeakChains = 12;

float peak_chunk(float seed) {
#ifdef __AVX2__
  __m256 a[kPeakChains];
  for (int j = 0; j < kPeakChains; ++j) a[j] = _mm256_set1_ps(seed + j);
  const __m256 m = _mm256_set1_ps(0.999f), c = _mm256_set1_ps(1e-3f);
  for (int r = 0; r < kPeakReps; ++r)
    for (int j = 0; j < kPeakChains; ++j) a[j] = _mm256_fmadd_ps(a[j], m, c);
  __m256 s = a[0];
  for (int j = 1; j < kPeakChains; ++j) s = _mm256_add_ps(s, a[j]);
  float out[8];
  _mm256_storeu_ps(out, s);
  return out[0] + out[7];
#else
  float a[kPeakChains * 8];
  for (int j = 0; j < kPeakChains * 8; ++j) a[j] = seed + j;
  for (int r = 0; r < kPeakReps; ++r)
    for (float& x : a) x = std::fma(x, 0.999f, 1e-3f);
  return a[0] + a[kPeakChains * 8 - 1];
#endif
}
constexpr double kPeakOpsPerIteration = double{kPeakChunks} * kPeakReps * kPeakChains * 8;

// The baselines report, besides the median time, their best iteration as a counter ("best_ns"):
// a peak is what the machine can do, so the fastest iteration (the one least disturbed by other
// processes) estimates it best, and a floor built on it stays a lower bound.
template <class F>
double best_of_iterations(benchmark::State& state, F&& body) {
  double best = 1e300;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  state.counters["best_ns"] = best;
  return best;
}

void BM_PeakOps(benchmark::State& state) {
  std::vector<float> sink(kPeakChunks);
  best_of_iterations(state, [&] {
    tbb::parallel_for(
        0, kPeakChunks, [&](int i) { sink[i] = peak_chunk(static_cast<float>(i)); },
        tbb::simple_partitioner());
    benchmark::DoNotOptimize(sink.data());
  });
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPeakOpsPerIteration));
}

float sum_floats(const float* p, std::size_t n) {
  std::size_t i = 0;
  float s = 0;
#ifdef __AVX2__
  __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
  for (; i + 32 <= n; i += 32) {
    a0 = _mm256_add_ps(a0, _mm256_loadu_ps(p + i));
    a1 = _mm256_add_ps(a1, _mm256_loadu_ps(p + i + 8));
    a2 = _mm256_add_ps(a2, _mm256_loadu_ps(p + i + 16));
    a3 = _mm256_add_ps(a3, _mm256_loadu_ps(p + i + 24));
  }
  float t[8];
  _mm256_storeu_ps(t, _mm256_add_ps(_mm256_add_ps(a0, a1), _mm256_add_ps(a2, a3)));
  for (float x : t) s += x;
#endif
  for (; i < n; ++i) s += p[i];
  return s;
}

// Parallel streaming read of n floats (both threads).
float stream_read(const float* p, std::size_t n) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 1 << 15), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& r, float acc) {
        return acc + sum_floats(p + r.begin(), r.size());
      },
      [](float a, float b) { return a + b; });
}

// Arg: buffer size in MiB.
void BM_StreamRead(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0)) * 1024 * 1024 / sizeof(float);
  std::vector<float> buf(n, 1.0f);
  best_of_iterations(state, [&] { benchmark::DoNotOptimize(stream_read(buf.data(), n)); });
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(n * sizeof(float)));
}

// ---------------------------------------------------------------------------------------------
// Configurations

struct EnvConfig {
  std::string method = "sweep";  // sweep | march | brute_force
  int n_phi = 32;
  int ls = 4;
  float lo = 2;
  int bands = 4;
  int size = kSize;

  ts::TerrainShadowConfig config() const {
    ts::TerrainShadowConfig c;
    c.method = method == "sweep"   ? ts::HorizonMethod::kSweep
               : method == "march" ? ts::HorizonMethod::kMarch
                                   : ts::HorizonMethod::kBruteForce;
    c.azimuths = n_phi;
    c.pyramid.level_step = ls;
    c.march.level_offset = lo;
    return c;
  }
  bool uses_march_params() const { return method == "march"; }
  std::string params_text() const {
    std::string s = "n_phi:" + std::to_string(n_phi);
    if (uses_march_params())
      s += "/ls:" + std::to_string(ls) + "/lo:" + std::to_string(static_cast<int>(lo));
    return s + "/bands:" + std::to_string(bands);
  }
  std::string params_json() const {
    std::ostringstream o;
    o << "{\"n_phi\": " << n_phi;
    if (uses_march_params()) o << ", \"ls\": " << ls << ", \"lo\": " << lo;
    o << ", \"bands\": " << bands << "}";
    return o.str();
  }
  // Minimal per-update work: horizons + wedges + transfer (+ pyramid for the march).
  double ops() const {
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
    return texels * (n_phi * (horizon + wedge_ops(bands)) + transfer_ops(bands)) + pyramid;
  }
  double bytes() const {  // heights in, transfer out
    return static_cast<double>(size) * size * 4.0 * (1 + bands * bands);
  }
};

// The one TerrainShadowing<N> alive for the benchmark that runs now (repetitions reuse it).
template <int N>
ts::TerrainShadowing<N>& shadowing_for(const std::string& key, const ts::TerrainShadowConfig& c,
                                       int size) {
  static std::string cached_key;
  static std::unique_ptr<ts::TerrainShadowing<N>> cached;
  if (!cached || cached_key != key) {
    cached.reset();
    cached = std::make_unique<ts::TerrainShadowing<N>>(c);
    cached->update(scene_field(size), tbr::kHeightScale);  // warm-up: allocations
    cached_key = key;
  }
  return *cached;
}

// Errors of a configuration, computed once (outside the timed loop) and kept for the records.
std::map<std::string, tbr::ErrorSummary>& errors() {
  static std::map<std::string, tbr::ErrorSummary> e;
  return e;
}

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
    default:
      env_update<4>(state, cfg, with_error, key);
  }
}

// ---------------------------------------------------------------------------------------------
// Breakdown

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

ts::HorizonParams env_horizon_params(int n_phi) {
  ts::HorizonParams p;
  p.azimuths = n_phi;
  p.height_scale = tbr::kHeightScale;
  p.clamp_at_zero = true;
  return p;
}

void BM_HorizonsSweep(benchmark::State& state) {
  const auto field = scene_field(kSize);
  const ts::HorizonParams p = env_horizon_params(32);
  ts::HorizonGrid grid;
  ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid);
  for (auto _ : state) {
    ts::sweep_horizons(*field, p, ts::TexelRect::all(*field), grid);
    benchmark::DoNotOptimize(grid.angles.data());
  }
  const double pairs = static_cast<double>(kSize) * kSize * p.azimuths;
  set_work(state, pairs * kSweepOpsPerPair, pairs * 4);
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

// Horizons -> wedge visibility -> transfer for every texel, as TerrainShadowing does it.
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

// ---------------------------------------------------------------------------------------------
// Local lights

struct LightDesc {
  glm::vec3 centre;
  float radius;
  glm::vec3 radiance;
};

// Lights `above` metres over the terrain at the given plane positions (fractions of the field).
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

// Minimal work of one light (see the header).
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
        ops +=
            (c.cap_method == ts::CapHorizons::kRadialSweep ? kSweepOpsPerPair : c.cap_horizons * ray) +
            kCapOpsPerStrip * c.cap_strips + kCapSetupOps;
    }
  return ops;
}

std::map<std::string, tbr::ErrorSummary>& light_errors() {
  static std::map<std::string, tbr::ErrorSummary> e;
  return e;
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
  if (!light_errors().count(key)) {
    std::vector<tbr::Light> ref;
    for (const LightDesc& l : lights) ref.push_back({l.centre, l.radius, l.radiance});
    light_errors()[key] = tbr::light_error(kSize, ref, irradiance);
  }
}

// ---------------------------------------------------------------------------------------------
// Local edit

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

// ---------------------------------------------------------------------------------------------
// Shading only (rotating environment)

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

// ---------------------------------------------------------------------------------------------
// Registration

struct CaseInfo {
  std::string key;          // Results key
  std::string title;        // summary row
  std::string kind;         // "case" or "sweep"
  std::string method;       // record's method
  std::string params_json;  // record's params
  int size = kSize;
  std::optional<double> goal_ms;
  EnvConfig env;  // for sweep points
  bool is_env = false;
};
std::vector<CaseInfo>& cases() {
  static std::vector<CaseInfo> c;
  return c;
}

benchmark::internal::Benchmark* timed(benchmark::internal::Benchmark* b, int iterations,
                                      int repetitions) {
  b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(iterations);
  if (repetitions > 1) b->Repetitions(repetitions)->DisplayAggregatesOnly(true);
  return b;
}

void register_env(const EnvConfig& cfg, const std::string& kind, int iterations, int repetitions,
                  std::optional<double> goal, bool with_error) {
  const std::string name = (kind == "sweep" ? "sweep/" : "env/") + cfg.method + "/" +
                           std::to_string(cfg.size) + "/" + cfg.params_text();
  timed(benchmark::RegisterBenchmark(name.c_str(), BM_EnvUpdate, cfg, with_error, name), iterations,
        repetitions);
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

void register_case(const std::string& key, const std::string& title, const std::string& method,
                   const std::string& params_json, int size, std::optional<double> goal) {
  CaseInfo c;
  c.key = key;
  c.title = title;
  c.kind = "case";
  c.method = method;
  c.params_json = params_json;
  c.size = size;
  c.goal_ms = goal;
  cases().push_back(c);
}

void register_benchmarks() {
  // Machine baselines.
  timed(benchmark::RegisterBenchmark("baseline/peak_ops", BM_PeakOps), 20, 5);
  timed(benchmark::RegisterBenchmark("baseline/stream_read_mib", BM_StreamRead), 20, 5)->Arg(8);
  timed(benchmark::RegisterBenchmark("baseline/stream_read_mib", BM_StreamRead), 3, 5)->Arg(256);

  // The main cases.
  EnvConfig sweep32;
  register_env(sweep32, "case", 10, kCaseReps, 10.0, true);
  EnvConfig march;
  march.method = "march";
  register_env(march, "case", 5, kCaseReps, 10.0, true);
  EnvConfig brute;
  brute.method = "brute_force";
  register_env(brute, "case", 1, 1, std::nullopt, true);

  timed(benchmark::RegisterBenchmark("part/pyramid/ls:4", BM_Pyramid), 20, kCaseReps);
  register_case("part/pyramid/ls:4", "pyramid build ls=4", "pyramid", "{\"ls\": 4}", kSize,
                std::nullopt);
  timed(benchmark::RegisterBenchmark("part/horizons/sweep/n_phi:32", BM_HorizonsSweep), 10,
        kCaseReps);
  register_case("part/horizons/sweep/n_phi:32", "horizons alone, sweep n_phi=32", "sweep",
                "{\"n_phi\": 32, \"part\": \"horizons\"}", kSize, std::nullopt);
  timed(benchmark::RegisterBenchmark("part/horizons/march/n_phi:32/ls:4/lo:2", BM_HorizonsMarch), 5,
        kCaseReps);
  register_case("part/horizons/march/n_phi:32/ls:4/lo:2", "horizons alone, march ls=4 lo=2",
                "march", "{\"n_phi\": 32, \"ls\": 4, \"lo\": 2, \"part\": \"horizons\"}", kSize,
                std::nullopt);
  timed(benchmark::RegisterBenchmark("part/transfer/n_phi:32/bands:4", BM_Transfer), 10, kCaseReps);
  register_case("part/transfer/n_phi:32/bands:4", "transfer alone (wedges + V*C), n_phi=32",
                "transfer", "{\"n_phi\": 32, \"bands\": 4, \"part\": \"transfer\"}", kSize,
                std::nullopt);

  const ts::TerrainShadowConfig defaults;
  const std::string cap_method = std::string("cap_") + ts::to_string(defaults.cap_method);
  const std::string cap_params = "{\"light_shading\": \"cap_horizon\", \"cap_method\": \"" +
                                 std::string(ts::to_string(defaults.cap_method)) +
                                 "\", \"cap_horizons\": " + std::to_string(defaults.cap_horizons) +
                                 ", \"cap_strips\": " + std::to_string(defaults.cap_strips) +
                                 ", \"lights\": ";
  timed(benchmark::RegisterBenchmark("light/cap", BM_Lights, ts::LightShading::kCapHorizon,
                                     std::string("light/cap")),
        10, kCaseReps)
      ->Arg(1)
      ->Arg(4);
  register_case("light/cap/1", "1 spherical light (default: cap horizon)", cap_method,
                cap_params + "1}", kSize, 5.0);
  register_case("light/cap/4", "4 spherical lights (cap horizon)", cap_method, cap_params + "4}",
                kSize, 20.0);
  timed(benchmark::RegisterBenchmark("light/sh_wedges", BM_Lights, ts::LightShading::kShWedges,
                                     std::string("light/sh_wedges")),
        5, kCaseReps)
      ->Arg(1);
  register_case("light/sh_wedges/1", "1 spherical light (thesis: SH wedges, 16 azimuths)",
                "sh_wedges_march",
                "{\"light_shading\": \"sh_wedges\", \"light_azimuths\": " +
                    std::to_string(defaults.light_azimuths) +
                    ", \"ls\": 4, \"lo\": 2, \"bands\": 4, \"lights\": 1}",
                kSize, 5.0);

  timed(benchmark::RegisterBenchmark("edit/16x16", BM_Edit), 20, kCaseReps);
  register_case("edit/16x16", "local edit 16x16 (apply_brush + update_edit)", "sweep",
                "{\"n_phi\": 32, \"bands\": 4, \"brush_radius_cells\": 8}", kSize, 2.0);

  EnvConfig big;
  big.size = kBigSize;
  big.n_phi = 64;
  register_env(big, "case", 1, 3, std::nullopt, false);

  timed(benchmark::RegisterBenchmark("shade/rotating_env", BM_Shade), 50, kCaseReps);
  register_case("shade/rotating_env", "shading only (rotate_z + shade_environment)", "shade",
                "{\"bands\": 4}", kSize, std::nullopt);
  timed(benchmark::RegisterBenchmark("baseline/shade_read_transfer", BM_ShadeReadBaseline), 50,
        kCaseReps);

  // Speed versus accuracy: one point per method and parameter set.
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
  for (int n_phi : {8, 32})
    for (int bands : {3, 5}) {
      EnvConfig c;
      c.n_phi = n_phi;
      c.bands = bands;
      register_env(c, "sweep", 3, 5, std::nullopt, true);
    }
}

// ---------------------------------------------------------------------------------------------
// Summary, records and chart

struct Record {
  const CaseInfo* info;
  std::optional<double> ms, floor_ms, baseline_ms;
  tbr::ErrorSummary error;
};

std::string jnum(std::optional<double> v, int precision = 6) {
  if (!v || !std::isfinite(*v)) return "null";
  std::ostringstream o;
  o.precision(precision);
  o << *v;
  return o.str();
}

std::string jstr(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

bool write_atomically(const std::string& path, const std::string& text) {
  const std::filesystem::path p(path);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  const std::filesystem::path tmp = p.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) return false;
    f << text;
    if (!f.flush()) return false;
  }
  std::filesystem::rename(tmp, p, ec);
  return !ec;
}

// 1-minute load average (other processes make the 2-thread timings slower), if available.
std::optional<double> load_average() {
  double l[1];
  if (getloadavg(l, 1) != 1) return std::nullopt;
  return l[0];
}

std::string records_json(const std::vector<Record>& records, const std::string& best) {
  std::ostringstream o;
  o << "{\n  \"group\": \"terrain\",\n  \"scene\": " << jstr(tbr::kSceneName)
    << ",\n  \"environment\": " << jstr(tbr::environment_name())
    << ",\n  \"reference\": " << jstr(tbr::reference_description())
    << ",\n  \"threads\": " << std::thread::hardware_concurrency()
    << ",\n  \"load_avg_at_end\": " << jnum(load_average())
    << ",\n  \"best_tradeoff_rule\": \"most accurate chart point within 10 ms; if none, smallest "
       "ms x rel_rms\""
    << ",\n  \"best_tradeoff\": " << jstr(best) << ",\n  \"records\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    const CaseInfo& c = *r.info;
    o << (i ? ",\n" : "\n") << "    {\"case\": " << jstr(c.key) << ", \"kind\": " << jstr(c.kind)
      << ", \"scene\": " << jstr(tbr::kSceneName) << ", \"method\": " << jstr(c.method)
      << ", \"params\": " << c.params_json << ", \"size\": " << c.size << ", \"ms\": " << jnum(r.ms)
      << ", \"floor_ms\": " << jnum(r.floor_ms)
      << ", \"ratio_to_floor\": " << jnum(pb::quotient(r.ms, r.floor_ms))
      << ", \"goal_ms\": " << jnum(c.goal_ms) << ", \"goal_met\": ";
    if (c.goal_ms && r.ms)
      o << (*r.ms <= *c.goal_ms ? "true" : "false");
    else
      o << "null";
    o << ", \"rel_rms_error\": " << jnum(r.error.rel_rms)
      << ", \"max_rel_error\": " << jnum(r.error.max_rel)
      << ", \"reference_rel_se\": " << jnum(r.error.ref_rel_se) << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

// Series of the chart: one colour per method and varied parameter.
std::string series_of(const CaseInfo& c) {
  if (c.env.method == "march") {
    if (c.env.n_phi != 32) return "march ls 4 lo 2, n_phi";
    return "march lo " + std::to_string(static_cast<int>(c.env.lo)) + ", ls (n_phi 32)";
  }
  if (c.env.method == "sweep") return c.env.bands != 4 ? "sweep, bands 3 and 5" : "sweep, n_phi";
  return "brute force (n_phi 32)";
}
std::string label_of(const CaseInfo& c) {
  if (c.env.method == "march" && c.env.n_phi == 32) return "ls" + std::to_string(c.env.ls);
  if (c.env.bands != 4)
    return "N" + std::to_string(c.env.bands) +
           (c.env.n_phi != 32 ? " n" + std::to_string(c.env.n_phi) : "");
  if (c.env.method == "brute_force") return "bf";
  return "n" + std::to_string(c.env.n_phi);
}
// Points of the chart: the sweep points and the brute-force case, with an error.
bool on_chart(const Record& r) {
  const CaseInfo& c = *r.info;
  return c.is_env && c.size == kSize && r.ms && r.error.rel_rms &&
         (c.kind == "sweep" || c.method == "brute_force");
}

std::string svg_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string chart_svg(const std::vector<Record>& records, const std::string& best_key) {
  struct Point {
    double ms, err;
    std::string series, label, key;
  };
  std::vector<Point> pts;
  for (const Record& r : records) {
    if (!on_chart(r)) continue;
    pts.push_back(
        {*r.ms, *r.error.rel_rms * 100, series_of(*r.info), label_of(*r.info), r.info->key});
  }
  const double W = 920, H = 600, left = 80, right = 250, top = 50, bottom = 70;
  const double pw = W - left - right, ph = H - top - bottom;
  std::ostringstream o;
  o.precision(5);
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left
    << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">Terrain shadows: "
       "full environment update, "
    << kSize << "x" << kSize << " " << tbr::kSceneName << ", 2 threads</text>\n"
    << "<text x=\"" << left
    << "\" y=\"40\" fill=\"#555\">irradiance error vs Monte Carlo reference ("
    << svg_escape(tbr::environment_name())
    << "); n = n_phi, ls = level step, N = SH bands</text>\n";
  if (pts.empty()) {
    o << "<text x=\"" << left + 20 << "\" y=\"" << top + ph / 2
      << "\">no points with a reference error in this run</text>\n</svg>\n";
    return o.str();
  }
  double tmin = 1e300, tmax = 0, emax = 0;
  for (const Point& p : pts) {
    tmin = std::min(tmin, p.ms);
    tmax = std::max(tmax, p.ms);
    emax = std::max(emax, p.err);
  }
  const double lx0 = std::floor(std::log10(tmin)), lx1 = std::ceil(std::log10(tmax));
  const double x_span = std::max(lx1 - lx0, 1.0);
  // Error axis: linear from 0 to a round step above the largest error.
  const double raw = emax / 5;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag <= 1   ? mag
                      : raw / mag <= 2 ? 2 * mag
                      : raw / mag <= 5 ? 5 * mag
                                       : 10 * mag;
  const double ymax = step * std::ceil(emax * 1.08 / step);
  auto X = [&](double ms) { return left + (std::log10(ms) - lx0) / x_span * pw; };
  auto Y = [&](double e) { return top + ph - e / ymax * ph; };

  o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (int d = static_cast<int>(lx0); d <= static_cast<int>(lx0 + x_span); ++d) {
    for (int m = 1; m <= 9; ++m) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > lx0 + x_span + 1e-9) break;
      const double x = X(v);
      o << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + ph
        << "\" stroke=\"" << (m == 1 ? "#bbb" : "#eee") << "\"/>\n";
      if (m == 1 || m == 2 || m == 5) {
        std::ostringstream label;
        label << v;
        o << "<text x=\"" << x << "\" y=\"" << top + ph + 16 << "\" text-anchor=\"middle\">"
          << label.str() << "</text>\n";
      }
    }
  }
  for (double e = 0; e <= ymax + 1e-12; e += step) {
    const double y = Y(e);
    o << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
      << "\" stroke=\"#eee\"/>\n<text x=\"" << left - 6 << "\" y=\"" << y + 4
      << "\" text-anchor=\"end\">" << e << "</text>\n";
  }
  // The 10 ms goal.
  if (10 >= std::pow(10.0, lx0) && 10 <= std::pow(10.0, lx0 + x_span)) {
    o << "<line x1=\"" << X(10) << "\" y1=\"" << top << "\" x2=\"" << X(10) << "\" y2=\""
      << top + ph << "\" stroke=\"#c33\" stroke-dasharray=\"6 4\"/>\n<text x=\"" << X(10) + 4
      << "\" y=\"" << top + 14 << "\" fill=\"#c33\">goal 10 ms</text>\n";
  }
  o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 24
    << "\" text-anchor=\"middle\">time of the full environment update, ms (log scale)</text>\n"
    << "<text x=\"22\" y=\"" << top + ph / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 22 " << top + ph / 2
    << ")\">relative RMS irradiance error, %</text>\n";

  // Pareto front (no other point both faster and more accurate).
  std::vector<Point> sorted = pts;
  std::sort(sorted.begin(), sorted.end(),
            [](const Point& a, const Point& b) { return a.ms < b.ms; });
  std::string path;
  double best_err = 1e300;
  for (const Point& p : sorted)
    if (p.err < best_err) {
      best_err = p.err;
      path +=
          (path.empty() ? "M" : " L") + std::to_string(X(p.ms)) + " " + std::to_string(Y(p.err));
    }
  o << "<path d=\"" << path << "\" fill=\"none\" stroke=\"#999\" stroke-dasharray=\"3 3\"/>\n";

  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                           "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  std::vector<std::string> series;
  for (const Point& p : pts)
    if (std::find(series.begin(), series.end(), p.series) == series.end())
      series.push_back(p.series);
  // Circles first, then each label at the first of six spots around its point that overlaps
  // no circle and no label placed so far.
  struct Box {
    double x0, y0, x1, y1;
    bool overlaps(const Box& b) const { return x0 < b.x1 && b.x0 < x1 && y0 < b.y1 && b.y0 < y1; }
  };
  std::vector<Box> taken;
  auto colour_of = [&](const Point& p) {
    return colours[(std::find(series.begin(), series.end(), p.series) - series.begin()) % 8];
  };
  for (const Point& p : pts) {
    const double x = X(p.ms), y = Y(p.err);
    o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"5\" fill=\"" << colour_of(p) << "\"";
    if (p.key == best_key) o << " stroke=\"black\" stroke-width=\"2\"";
    o << "><title>" << svg_escape(p.key) << ": " << p.ms << " ms, " << p.err
      << " %</title></circle>\n";
    taken.push_back({x - 5, y - 5, x + 5, y + 5});
  }
  for (const Point& p : pts) {
    const double x = X(p.ms), y = Y(p.err);
    const double w = 6.0 * p.label.size(), h = 10;
    const double spots[6][2] = {{7, -4}, {7, 13}, {-7 - w, -4}, {-7 - w, 13}, {8, 4}, {-8 - w, 4}};
    Box chosen{};
    for (int k = 0; k < 6; ++k) {
      const Box b{x + spots[k][0], y + spots[k][1] - h, x + spots[k][0] + w, y + spots[k][1]};
      if (k == 0) chosen = b;
      bool free = true;
      for (const Box& t : taken)
        free = free && !(t.overlaps(b) && !(t.x0 == x - 5 && t.y0 == y - 5));
      if (free) {
        chosen = b;
        break;
      }
    }
    taken.push_back(chosen);
    o << "<text x=\"" << chosen.x0 << "\" y=\"" << chosen.y1 << "\" font-size=\"10\" fill=\""
      << colour_of(p) << "\">" << svg_escape(p.label) << "</text>\n";
  }
  const double lx = left + pw + 16;
  double ly = top + 10;
  o << "<text x=\"" << lx << "\" y=\"" << ly << "\" font-weight=\"bold\">method</text>\n";
  for (std::size_t s = 0; s < series.size(); ++s) {
    ly += 20;
    o << "<circle cx=\"" << lx + 6 << "\" cy=\"" << ly - 4 << "\" r=\"5\" fill=\"" << colours[s % 8]
      << "\"/><text x=\"" << lx + 16 << "\" y=\"" << ly << "\">" << svg_escape(series[s])
      << "</text>\n";
  }
  ly += 28;
  o << "<text x=\"" << lx << "\" y=\"" << ly
    << "\" fill=\"#555\">dashed grey: Pareto front</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 16
    << "\" fill=\"#555\">ringed: best trade-off</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 32
    << "\" fill=\"#555\">n_phi 32 unless labelled nK</text>\n"
    << "<text x=\"" << lx << "\" y=\"" << ly + 48
    << "\" fill=\"#555\">march: pyramid build included</text>\n";
  o << "</svg>\n";
  return o.str();
}

std::string g_records_out, g_chart_out;

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  const auto peak_ns = r.counter("baseline/peak_ops", "best_ns");
  const auto l3_ns = r.counter("baseline/stream_read_mib/8", "best_ns");
  const auto dram_ns = r.counter("baseline/stream_read_mib/256", "best_ns");
  const std::optional<double> ops_per_ns = pb::quotient(kPeakOpsPerIteration, peak_ns);
  const std::optional<double> l3_bpns = pb::quotient(8.0 * 1024 * 1024, l3_ns);
  const std::optional<double> dram_bpns = pb::quotient(256.0 * 1024 * 1024, dram_ns);

  auto floor_ms = [&](const std::string& key) -> std::optional<double> {
    const auto ops = r.counter(key, "ops");
    const auto bytes = r.counter(key, "bytes");
    if (!ops || !bytes || !ops_per_ns) return std::nullopt;
    const auto bw = *bytes > kL3Bytes ? dram_bpns : l3_bpns;
    double f = *ops / *ops_per_ns;
    if (bw) f = std::max(f, *bytes / *bw);
    return f * 1e-6;
  };
  auto ms = [&](const std::string& key) { return pb::scale(r.real_ns(key), 1e-6); };

  std::vector<Record> records;
  for (const CaseInfo& c : cases()) {
    Record rec{&c, ms(c.key), floor_ms(c.key), std::nullopt, {}};
    if (auto e = errors().find(c.key); e != errors().end()) rec.error = e->second;
    if (auto e = light_errors().find(c.key); e != light_errors().end()) rec.error = e->second;
    if (rec.ms) records.push_back(rec);
  }

  // Best trade-off: the most accurate chart point within the 10 ms goal; when none meets it,
  // the one with the smallest time x error (the knee of the Pareto front on log-log axes).
  std::string best;
  double best_err = 1e300, best_product = 1e300;
  for (const Record& rec : records) {
    if (!on_chart(rec) || *rec.ms > 10 || *rec.error.rel_rms >= best_err) continue;
    best_err = *rec.error.rel_rms;
    best = rec.info->key;
  }
  if (best.empty())
    for (const Record& rec : records) {
      if (!on_chart(rec) || *rec.ms * *rec.error.rel_rms >= best_product) continue;
      best_product = *rec.ms * *rec.error.rel_rms;
      best = rec.info->key;
    }

  auto goal_of = [](const CaseInfo& c) {
    return c.goal_ms ? pb::Goal::value_at_most(*c.goal_ms) : pb::Goal::none();
  };
  auto err_note = [](const tbr::ErrorSummary& e) {
    if (!e.rel_rms) return std::string();
    char buf[96];
    std::snprintf(buf, sizeof buf, "error rel_rms %.2f%%, max_rel %.1f%%", 100 * *e.rel_rms,
                  100 * e.max_rel.value_or(0));
    return std::string(buf);
  };
  const std::string brute_key = "env/brute_force/256/n_phi:32/bands:4";
  const std::string sweep_key = "env/sweep/256/n_phi:32/bands:4";
  for (const Record& rec : records) {
    const CaseInfo& c = *rec.info;
    if (c.kind != "case") continue;
    std::optional<double> baseline;
    std::string note;
    if (c.is_env && c.key != brute_key && c.size == kSize) {
      baseline = ms(brute_key);
      note = "baseline: brute-force horizons (same update)";
    } else if (c.key == "light/cap/4") {
      baseline = pb::scale(ms("light/cap/1"), 4);
      note = "baseline: 4 x one light (ratio 1 = linear)";
    } else if (c.key == "edit/16x16") {
      baseline = ms(sweep_key);
      note = "baseline: full update (sweep)";
      if (auto p = r.counter(c.key, "pairs"), t = r.counter(c.key, "texels"); p && t)
        note += "; " + std::to_string(static_cast<long>(*p)) + " pairs, " +
                std::to_string(static_cast<long>(*t)) + " texels recomputed";
    } else if (c.key == "shade/rotating_env") {
      baseline = ms("baseline/shade_read_transfer");
      note = "baseline: streaming read of the stored transfer";
    } else if (c.key == "light/cap/1") {
      baseline = ms("light/sh_wedges/1");
      note = "baseline: the thesis's SH-wedge light (same run); thesis GTX 560: ~16 ms per light";
    } else if (c.key == "light/sh_wedges/1") {
      note = "thesis GTX 560: ~16 ms per light";
    } else if (c.size == kBigSize) {
      note = "Timonen 2010 GTX 280: ~43 ms";
    } else if (c.key == "part/pyramid/ls:4") {
      note = "thesis GTX 560: 1.7 ms";
    }
    const std::string en = err_note(rec.error);
    if (!en.empty()) note += (note.empty() ? "" : "; ") + en;
    pb::Row& row =
        s.add_vs_baseline(c.title, "ms", rec.ms, baseline, goal_of(c), rec.floor_ms, note);
    if (!baseline) row.ratio_def.clear();
  }
  for (const Record& rec : records) {
    const CaseInfo& c = *rec.info;
    if (c.kind != "sweep") continue;
    pb::Row& row =
        s.add_vs_baseline("sweep: " + c.env.method + " " + c.env.params_text(), "ms", rec.ms,
                          std::nullopt, pb::Goal::none(), rec.floor_ms, err_note(rec.error));
    row.ratio_def.clear();
  }
  pb::Row peak;
  peak.name = "vector peak, 2 threads (floor unit)";
  peak.unit = "ops/ns";
  peak.value = ops_per_ns;
  peak.note =
      "AVX2 FMA chains, 8 lanes; an op = one lane of one instruction; best iteration (also the "
      "stream reads)";
  s.add(peak);
  pb::Row l3;
  l3.name = "stream read 8 MiB (L3), 2 threads";
  l3.unit = "GB/s";
  l3.value = l3_bpns;
  s.add(l3);
  pb::Row dram;
  dram.name = "stream read 256 MiB (DRAM), 2 threads";
  dram.unit = "GB/s";
  dram.value = dram_bpns;
  s.add(dram);

  if (!g_records_out.empty()) {
    if (write_atomically(g_records_out, records_json(records, best)))
      std::cout << "records written to " << g_records_out << "\n";
    else
      std::cerr << "bench_terrain: cannot write " << g_records_out << "\n";
  }
  if (!g_chart_out.empty()) {
    if (write_atomically(g_chart_out, chart_svg(records, best)))
      std::cout << "chart written to " << g_chart_out << "\n";
    else
      std::cerr << "bench_terrain: cannot write " << g_chart_out << "\n";
  }
  if (!best.empty()) std::cout << "best trade-off: " << best << "\n";
  return s;
}

// Removes "--NAME=VALUE" from argv; returns VALUE ("" if absent).
std::string take_flag(int& argc, char** argv, const std::string& name) {
  std::string value;
  const std::string prefix = "--" + name + "=";
  int w = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind(prefix, 0) == 0) {
      value = a.substr(prefix.size());
      continue;
    }
    argv[w++] = argv[i];
  }
  argc = w;
  argv[argc] = nullptr;
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  g_records_out = take_flag(argc, argv, "records_out");
  g_chart_out = take_flag(argc, argv, "chart_out");
  register_benchmarks();
  return pb::run_main(argc, argv, "terrain", summarize);
}
