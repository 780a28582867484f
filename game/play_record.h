// What one headless run of the main job measured, as the `play` benchmark group writes it
// (`penumbra_play --bench FILE`, `./penumbra bench play` -> build/bench/play.json; fields in
// docs/play.md). Plain data; private to penumbra_play.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace penumbra::play {

struct FrameSample {
  double wall_ms = 0;    // simulation + render record and submit (which waits for the GPU
                         // when it is frames behind)
  double sim_ms = 0;     // the job graph's frame
  double render_ms = 0;  // Renderer::render
};

// One system of the job graph over the timed frames: CPU time and the work it reported
// (jobs::report_work: items done and skipped as unchanged, mean per frame).
struct SystemRow {
  std::string name;
  double mean_ms = 0, max_ms = 0;
  bool reported = false;  // false: the system does not report its work
  double done_per_frame = 0, skipped_per_frame = 0;
};

struct PlayRecord {
  // The run.
  std::string scene, device, cpu, date;
  int width = 0, height = 0, frames = 0, warmup = 0, cores = 0;
  int sim_threads = 0;               // the job graph's arena
  std::string lavapipe_threads;      // LP_NUM_THREADS as the renderer saw it ("" when unset)
  double load_average = -1;          // 1-minute load average at the start (-1: unknown)
  std::vector<FrameSample> samples;  // measured frames (after warm-up and the GPU-timed frames,
                                     // no captures)
  double empty_frame_ms = 0;  // median frame of an empty packet (clear + tonemap), over frames
                              // rendered before and after the run (half each)
  double empty_frame_before_ms = 0, empty_frame_after_ms = 0;  // each half's median
  // Mean GPU time per pass (timestamps), over `gpu_timed_frames` frames rendered right after the
  // warm-up and left out of `samples`: on lavapipe timing a frame slows it (docs/play.md).
  std::map<std::string, double> gpu_pass_ms;
  double gpu_frame_ms = 0;
  int gpu_timed_frames = 0;
  // Terrain level of detail: triangles drawn (mean per frame), the same view at full detail,
  // and the last frame's image against full detail (pixels off by more than 24 of 255).
  float terrain_lod_pixels = 0;
  double terrain_triangles = 0;
  std::uint64_t terrain_triangles_full = 0;
  double lod_differing_fraction = -1;
  int lod_max_difference = -1;
  // Light re-shading (light_refresh.h), over the timed frames.
  std::size_t light_tiles = 0;
  double light_tiles_per_frame = 0;   // mean tiles re-shaded
  double light_worst_observed = 0;    // largest real change of a re-shaded texel / its irradiance
  double light_visible_fraction = 0;  // re-shaded texels that had changed by over the tolerance
  double light_worst_deferred = 0;    // largest bound of a tile left waiting / its threshold
  // The turning environment's re-shading (environment_refresh.h): mean tiles re-shaded and
  // over the tolerance per frame (of light_tiles: both use the same tiles).
  double environment_tiles_per_frame = 0, environment_stale_per_frame = 0;
  std::vector<SystemRow> systems;     // in the job graph's order, sync points left out
  // Other thread splits of the same scene, run as child processes (their JSON records).
  std::vector<std::string> splits;
};

// Frame statistics of a record.
struct FrameSummary {
  double mean_ms = 0, median_ms = 0, p95_ms = 0, fps = 0, sim_ms = 0, render_ms = 0;
};
FrameSummary summarize(const std::vector<FrameSample>& samples);

// The record as JSON ("format": "penumbra-play", "version": 1).
std::string to_json(const PlayRecord& record);

// Machine facts for the record: CPU model, online cores, 1-minute load average, UTC date.
void describe_machine(PlayRecord& record);

// Runs this executable again with `args` and the environment variable `env` (NAME=VALUE) added;
// returns its exit status (-1 when it could not start).
int run_child(const std::vector<std::string>& args, const std::string& env);

}  // namespace penumbra::play
