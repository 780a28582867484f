// What the terrain group's benchmark files share (terrain_bench_main.cpp lists the files and
// the cases): the scene and environment, the per-case work counters that become floors, the
// cached TerrainShadowing, the configuration of an environment update, and the table of
// registered cases that the summary and the records are written from.
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
//   exact transfer:  (default, transfer.h) per (texel, azimuth) the tangent plane 2 + arctangent
//                    10 + max 1 and a wedge at N + 1 bands; per texel 1 per non-zero
//                    component of a coupling G_ij and 3 N^2 to weigh them by the normal
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
// Threading: everything here runs on the benchmark's thread (the systems use TBB inside).
#pragma once

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench_registry.h"
#include "penumbra/sh/product.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "terrain_bench_reference.h"

namespace penumbra::terrain_bench {

namespace pb = penumbra::bench;
namespace ts = penumbra::terrain_shadow;
namespace data = penumbra::data;
namespace sh = penumbra::sh;
namespace tbr = penumbra::bench::terrain;

inline constexpr int kSize = 256;
inline constexpr int kCaseReps = 9;  // repetitions of the main cases (the median is reported)
inline constexpr int kBigSize = 1024;
inline constexpr double kL3Bytes = 32.0 * 1024 * 1024;

// Every terrain benchmark runs a fixed number of iterations, `repetitions` times, wall clock.
inline pb::Timing runs(int iterations, int repetitions) {
  return {.unit = benchmark::kMillisecond, .iterations = iterations, .repetitions = repetitions};
}

// ---------------------------------------------------------------------------------------------
// Op counts (see the top of this file)

inline constexpr double kSweepOpsPerPair = 16;
inline constexpr double kMarchOpsPerSample = 8;
inline constexpr double kAtanOps = 10;
inline constexpr double kPyramidOpsPerSample = 6;
inline constexpr double kCapOpsPerStrip = 10;
inline constexpr double kCapSetupOps = 20;

double wedge_ops(int n);
template <int N>
double transfer_ops() {
  return 2.0 * N * N + sh::factored_term_count<N>();
}
double transfer_ops(int n);
// The exact transfer per texel: tangent planes and wedges at n + 1 bands for n_phi azimuths,
// then the couplings.
double exact_transfer_ops(int n, int n_phi);

// Samples of the march (d_0 = 1, d_{i+1} = d_i + sr^i, `levels` of them) used for a light at
// plane distance `dl` cells: up to and including the first beyond it (horizon_march.cpp).
int march_samples_to(double dl, int levels, int level_step);
int march_samples_all(int levels);
int pyramid_levels(int size, int level_step);

// Per-iteration work of a case, reported as counters so the summary can turn it into a floor.
void set_work(benchmark::State& state, double ops, double bytes);

// ---------------------------------------------------------------------------------------------
// Same-run machine baselines (baselines_bench.cpp): vector peak and streaming-read bandwidth

inline constexpr int kPeakChunks = 64;
inline constexpr int kPeakReps = 16384;
inline constexpr int kPeakChains = 12;
inline constexpr double kPeakOpsPerIteration = double{kPeakChunks} * kPeakReps * kPeakChains * 8;

// Parallel streaming read of n floats (both threads).
float stream_read(const float* p, std::size_t n);

// ---------------------------------------------------------------------------------------------
// Scene and environment

// The environment's horizons as the update sweeps them (n_phi azimuths, clamped at zero).
ts::HorizonParams env_horizon_params(int n_phi);

// The scene at size x size, loaded once per size (not thread-safe: call it from the
// benchmark's thread).
std::shared_ptr<const data::HeightField> scene_field(int size);

template <int N>
const sh::CoeffsRgb<N>& environment_sh() {
  static const sh::CoeffsRgb<N> radiance = tbr::environment_sh<N>();
  return radiance;
}

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

// Irradiance errors of the cases that have one (environment updates, lights), by Results key:
// computed once, outside the timed loop, and kept for the summary and the records.
std::map<std::string, tbr::ErrorSummary>& errors();

// ---------------------------------------------------------------------------------------------
// An environment update's configuration (methods in env_update_bench.cpp)

struct EnvConfig {
  std::string method = "sweep";  // sweep | march | brute_force
  int n_phi = 32;
  int ls = 4;
  float lo = 2;
  int bands = 4;
  int size = kSize;
  std::string transfer = "exact";  // exact | truncated (TransferMethod)

  ts::TerrainShadowConfig config() const;
  bool uses_march_params() const { return method == "march"; }
  std::string params_text() const;  // "n_phi:32/bands:4[/transfer:truncated]": in the name
  std::string params_json() const;  // the record's params
  // Minimal per-update work: horizons + wedges + transfer (+ pyramid for the march).
  double ops() const;
  double bytes() const;  // heights in, transfer out
};

// ---------------------------------------------------------------------------------------------
// Registered cases: one summary row and one record each, in registration order

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
std::vector<CaseInfo>& cases();

// A case that is not an environment update (those go through register_env_*).
void register_case(const std::string& key, const std::string& title, const std::string& method,
                   const std::string& params_json, int size, std::optional<double> goal);

// The benchmark files' registrations, called in this order by terrain_bench_main.cpp.
void register_machine_baselines();  // baselines_bench.cpp
void register_env_cases();          // env_update_bench.cpp: sweep, march, brute force at 256^2
void register_horizon_parts();      // horizons_bench.cpp: pyramid, sweep, march alone
void register_transfer_part();      // transfer_bench.cpp
void register_lights();             // light_bench.cpp
void register_edit();               // edit_bench.cpp
void register_env_big();            // env_update_bench.cpp: 1024^2
void register_shade();              // shade_bench.cpp, with its streaming-read baseline
void register_env_sweep();          // env_update_bench.cpp: speed versus accuracy points
// vcpu_probe_bench.cpp: the machine's moment here, as probe/vcpu_sweep/<n> (n: the probes
// registered before it), `label` naming the cases that follow ("edit") or "after ..."; the
// labels in order.
void register_vcpu_probe(const std::string& label);
std::vector<std::string>& vcpu_probe_labels();

}  // namespace penumbra::terrain_bench
