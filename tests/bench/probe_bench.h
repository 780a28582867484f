// Shared between the files of the probes benchmark group (probe_bench.cpp: tetrahedralization
// against tetgen, the walk frames, floors, summary, main; probe_records.cpp: the
// speed-versus-accuracy sweep, the records and the chart).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench_report.h"

namespace penumbra::bench::probes {

inline constexpr int kThreads = 2;
inline constexpr double kGoalMs = 0.5;           // issue 12: 10,000 entities, 2 cores
inline constexpr double kGoalEntities = 10'000;  // the goal's entities

// Counted operations of one walk + interpolation (probe_tet_walk.cpp): per cell tested, the
// barycentric weights T^-1 (p - p3) and l3 = 1 - l0 - l1 - l2 (3 + 9 + 3) and the most negative
// weight (4); per interpolation 4 probes x 3 channels x bands^2 multiply-adds.
inline double cell_test_flops() {
  return 19;
}
inline double interpolation_flops(int bands) {
  return 12.0 * bands * bands;
}
// Bytes touched (ProbeTetWalk's hot records, whole lines): per cell tested its record (64:
// transform xyz and vertices); per interpolation the four probes' records (3 x bands^2 SH
// floats and the position, padded to lines: 128 bytes at 3 bands), the point (12), the cached
// cell (4 read, 4 written) and the RGB result at the cloud's bands (3 x bands^2 floats written,
// as ProbeLighting holds). Before the hot records: 96 per cell (ProbeCell 32 + mat4 64) and 644
// per 3-band interpolation (SH only, and a 4-band result of 192 bytes).
inline double cell_test_bytes() {
  return 64;
}
inline double probe_record_bytes(int bands) {
  return 64.0 * ((3 * bands * bands + 3 + 15) / 16);
}
inline double interpolation_bytes(int bands) {
  return 4 * probe_record_bytes(bands) + 12 + 8 + 12.0 * bands * bands;
}

// The speed-versus-accuracy sweep (probe_records.cpp): clouds in the accuracy scene of
// tests/probe_cloud/probe_accuracy_scene.h, a frame of kSweepEntities moving entities each.
struct SweepCase {
  std::string key, cloud;  // cloud: "grid 1 m", "random 400", "hand-placed"
  float spacing = 0;       // grid spacing (0: not a grid)
  int bands = 3;
  bool windowed = false;  // the probes' irradiance windowed against ringing (dering_irradiance)
};
inline constexpr int kSweepEntities = 10'000;
const std::vector<SweepCase>& sweep_cases();
void register_sweep_benchmarks();

// Where --records_out and --chart_out write ("": not written).
struct Outputs {
  std::string records_path, chart_path;
};
// The tetrahedralization and frame cases of probe_bench.cpp, for the records.
struct CaseInfo {
  std::string key, kind, scene, method;  // kind: tetrahedralize, frame
  std::string baseline_key;              // same-run baseline ("" none)
  double size = 0;                       // points or entities
  int bands = 3;
  std::optional<double> goal_ms;
};
std::vector<CaseInfo> bench_cases();
void write_records(const Results& r, double ns_per_fma, const Outputs& out);

}  // namespace penumbra::bench::probes
