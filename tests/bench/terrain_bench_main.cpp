// Benchmark group "terrain": speed and accuracy of the terrain shadow system
// (systems/terrain_shadow, [Meier13] ch. 4-6) on this machine's 2 threads.
//
//   build/release/tests/bench/bench_terrain [--benchmark_* flags] [--summary_out=PATH]
//       [--records_out=PATH.json] [--chart_out=PATH.svg]
//
// Cases (256 x 256 "mountains" unless said otherwise, 4 SH bands, median over repetitions), one
// file per method measured, registered in this order:
//  - baseline/...  baselines_bench.cpp: vector peak and streaming-read bandwidth measured in
//                  this run, the units of the floors (terrain_bench_common.h).
//  - probe/...     vcpu_probe_bench.cpp: the one-thread sweep on each vCPU at once, before each
//                  goal case's group and after the last (env/1024): the moment each one met.
//  - env/...       env_update_bench.cpp: TerrainShadowing::update(): normals, pyramid (march
//                  only: the default lights sweep), horizons, transfer. Sweep (default,
//                  n_phi = 32), march (ls 4, lo 2), brute force (1 iteration). Goal <= 10 ms
//                  (thesis table 6.6 on a GTX 560: 1.7 ms pyramid + 6.7 ms environment pass).
//  - part/...      the breakdown: pyramid alone, horizons alone (sweep, march, the sweep with
//                  its AVX2 copy forced): horizons_bench.cpp; transfer alone: transfer_bench.cpp.
//  - light/...     light_bench.cpp: add_spherical_light, 1 and 4 lights with the default shading
//                  (cap horizon: the horizon towards the light, exact cap integral), 1 light
//                  with the thesis's SH wedges (16 azimuths). Goal <= 5 ms per light (thesis:
//                  ~16 ms).
//  - edit/16x16    edit_bench.cpp: apply_brush (crater/raise alternately, radius 8 m) +
//                  update_edit. Goal <= 2 ms.
//  - env/1024      1024 x 1024, 64 azimuths, sweep (Timonen and Westerholm 2010: ~43 ms a
//                  frame on a GTX 280).
//  - shade         shade_bench.cpp: rotating environment: rotate_z of the SH radiance +
//                  shade_environment from the stored transfer; its baseline, a streaming read
//                  of the stored transfer.
//  - sweep/...     speed versus accuracy: one full update per configuration (n_phi, ls/lo,
//                  bands), few iterations, with its irradiance error against the Monte Carlo
//                  reference (rel_rms, max_rel at subsampled receivers, one HDR map).
//
// Summary rows, records and chart: terrain_summary.cpp, terrain_records.cpp. --records_out
// writes one JSON record per measured case and per sweep point (scene, method, params, size,
// ms, floor_ms, rel_rms_error, max_rel_error); --chart_out the speed-versus-accuracy chart as
// SVG. Both written atomically (temporary file, then rename).
#include "terrain_records.h"

namespace {

namespace tb = penumbra::terrain_bench;

void register_benchmarks() {
  tb::register_machine_baselines();
  tb::register_vcpu_probe("env update");
  tb::register_env_cases();
  tb::register_vcpu_probe("horizons");
  tb::register_horizon_parts();
  tb::register_vcpu_probe("transfer");
  tb::register_transfer_part();
  tb::register_vcpu_probe("lights");
  tb::register_lights();
  tb::register_vcpu_probe("edit");
  tb::register_edit();
  tb::register_vcpu_probe("1024^2");
  tb::register_env_big();
  tb::register_vcpu_probe("after 1024^2");
  tb::register_shade();
  tb::register_env_sweep();
}

}  // namespace

int main(int argc, char** argv) {
  tb::Outputs out;
  out.records_path = tb::pb::take_flag(argc, argv, "records_out");
  out.chart_path = tb::pb::take_flag(argc, argv, "chart_out");
  return tb::pb::run_group(argc, argv, "terrain", register_benchmarks,
                           [&](const tb::pb::Results& r) { return tb::summarize(r, out); });
}
