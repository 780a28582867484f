// Shared between the files of the blockers benchmark group (blocker_bench.cpp: kernels,
// floors, summary, main; blocker_frame_bench.cpp: frames; blocker_sweep_bench.cpp: speed versus
// accuracy; blocker_records.cpp: records and chart): scenes, counted operations, summary rows.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bench_report.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"

namespace penumbra::bench::blockers {

namespace ba = penumbra::blocker_accumulation;

// What the group's cases share: two worker threads (the machine's cores), blocks of 1,024
// receivers per parallel_for task, and issue 11's goal (100,000 receivers x 400 blockers in 30 ms).
inline constexpr int kThreads = 2;
inline constexpr std::size_t kBlock = 1024;
inline constexpr double kGoalMs = 30;

std::vector<glm::vec3> receiver_grid();
std::vector<ba::WorldSphere> scattered_spheres(int count);
double view_flops();
double add_log_flops(int bands);
double exp_flops(int bands, double squares);
double shade_flops(int bands, double squares);
double depth_eval_flops(int bands);
void register_frame_benchmarks();
void summarize_frames(const Results& r, Summary& s, double ns_per_fma);

// The frames' scenes by name ("scattered:50", "scattered:400", "objects:400"; groups empty:
// every sphere its own group) and cases (blocker_frame_bench.cpp).
struct FrameScene {
  std::vector<ba::WorldSphere> spheres;
  std::vector<ba::BlockerGroup> groups;
};
const FrameScene& frame_scene(const std::string& name);
struct FrameCaseInfo {
  std::string key, scene, method;  // Results key; method: all_pairs, grid, hierarchy, clusters
};
std::vector<FrameCaseInfo> frame_cases();

// Speed versus accuracy (blocker_sweep_bench.cpp): one frame per configuration on a window of
// the frames' receivers.
struct SweepPoint {
  std::string key, scene, method;  // method: all_pairs, grid, hierarchy, clusters
  int bands = 4;
  float min_sin = 0;    // 0 for all pairs
  float far_error = 0;  // ReceiverClusterSettings::far_error (clusters only)
  int receivers = 0;
};
const std::vector<SweepPoint>& sweep_points();
void register_sweep_benchmarks();

// Where --records_out and --chart_out write ("": not written), and the records and the
// speed-versus-accuracy chart of a run, written atomically (blocker_records.cpp).
struct Outputs {
  std::string records_path, chart_path;
};
void write_records(const Results& r, double ns_per_fma, const Outputs& out);
Row& add_row(Summary& s, std::string name, std::string unit, std::optional<double> value,
             std::optional<double> baseline, Goal goal, std::optional<double> floor,
             std::string note);

}  // namespace penumbra::bench::blockers
