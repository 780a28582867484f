// Shared between the files of the spherical_lights benchmark group (spherical_light_bench.cpp:
// scenes, kernels, frames, floors, summary, main; spherical_light_records.cpp: records and the
// speed-versus-accuracy chart).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench_report.h"

namespace penumbra::bench::spherical {

// One timed frame configuration: a scene ("objects:64": 100,000 receivers, 8 boxes of 8 SLs;
// "squirrel:14": 21,000 receivers, one box of 14 SLs), a blocking mode ("per_sphere",
// "per_object"), min_sin, and whether it is one of the goal frames ("frame") or a
// speed-versus-accuracy point ("sweep"); the method: every receiver on its own, or receiver
// clusters (SlReceiverClusters, cell 1.5 m, far_ratio).
struct FrameCaseInfo {
  std::string key, kind, scene, blocking;
  std::string method;  // "receivers": irradiance() per receiver; "clusters": shade(clusters)
  float min_sin = 0.05f;
  float far_ratio = 0;  // clusters only
  double receivers = 0, lights = 0;
  std::optional<double> goal_ms;
};
std::vector<FrameCaseInfo> frame_cases();

// Where --records_out and --chart_out write ("": not written).
struct Outputs {
  std::string records_path, chart_path;
};
// Floor of a frame (counted operations x ns per FMA / threads), ms.
std::optional<double> frame_floor_ms(const Results& r, const std::string& key, double ns_per_fma);
void write_records(const Results& r, double ns_per_fma, const Outputs& out);

}  // namespace penumbra::bench::spherical
