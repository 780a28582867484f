// Shared between the two files of the blockers benchmark group (blocker_bench.cpp: kernels,
// floors, summary; blocker_frame_bench.cpp: frames): scenes, counted operations, summary rows.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bench_report.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"

namespace penumbra::bench::blockers {

namespace ba = penumbra::blocker_accumulation;

std::vector<glm::vec3> receiver_grid();
std::vector<ba::WorldSphere> scattered_spheres(int count);
double view_flops();
double add_log_flops(int bands);
double exp_flops(int bands, double squares);
double shade_flops(int bands, double squares);
double depth_eval_flops(int bands);
void register_frame_benchmarks();
void summarize_frames(const Results& r, Summary& s, double ns_per_fma);
Row& add_row(Summary& s, std::string name, std::string unit, std::optional<double> value,
             std::optional<double> baseline, Goal goal, std::optional<double> floor,
             std::string note);

}  // namespace penumbra::bench::blockers
