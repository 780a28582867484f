// The main job's options and its two renderer loops (play_render.cpp); private to penumbra_play.
#pragma once

#include <cstddef>
#include <string>

namespace penumbra::play {

struct Options {
  // "valley": the game (valley_game.h); "terrain": the DEM demo (terrain_demo.h); "sample":
  // particles.
  std::string scene = "valley";
  std::string input;      // valley: replay this recording (headless default: the committed one)
  std::string record;     // valley: write the session's input here at the end
  bool autopilot = false;  // valley: the scripted player (valley_autopilot.h) plays
  std::string data;               // ../shared/data when empty
  int frames = 0;                 // 0: 300 headless, until the window closes otherwise
  int threads = 0;
  std::size_t particles = 200'000;
  std::string trace, dot;
  std::string out;        // screenshots (*.png) go here; empty: none
  int screenshots = 3;    // headless: spread over the run (first after warm-up, middle, last)
  bool headless = false;  // force offscreen even with a display
  bool render = true;     // --no-render: simulation only (the pre-renderer main job)
  bool validation = false;
  std::string device;  // render/device_select.h
  int width = 960, height = 540;
  std::size_t points = 50'000;    // particles drawn at most (every k-th); 0: all
  float terrain_lod_pixels = -1;  // < 0: the scene's own (render::ViewSettings)
  float light_budget = -1;        // < 0: LightRefreshConfig's (terrain demo)
  int boulders = -1;              // < 0: BoulderConfig's count (terrain demo)
  bool show_spheres = false;      // the boulders' sphere sets as wire circles
  bool sun_shadows = false;       // the meshes' per-pixel environment shading (shadow maps)
  bool follow_pair = false;       // camera on the colour-bleeding boulder pair (key C toggles)
  bool probes_debug = false;      // the probe cloud's debug views (probe_demo.h; key P toggles)
  int probe_objects = -1;         // < 0: ProbeDemoConfig's count; 0: no probe cloud
  float boulder_detail = -1;      // < 0: BoulderConfig's simplify_error; 0: full meshes
  std::string bench;              // headless: write the run's record (play_record.h) here
  std::string settings;           // a tuned settings file (./penumbra tune; docs/tune.md)
  std::string bench_splits;       // "T:L,...": also run these splits (threads, LP_NUM_THREADS)
  int empty_frames = 120;         // --bench: frames of an empty packet, the baseline (half
                                  // before the run, half after)
  int gpu_timing_frames = 40;     // headless: frames after the warm-up whose GPU passes are
                                  // timed (at most half the frames after it)
};

// With a window the main job times the GPU passes (for the overlay) of one frame in this many
// (render::Renderer::set_timing_interval): on lavapipe a timed frame takes about twice as long
// as an untimed one (docs/play.md). Headless, only the first Options::gpu_timing_frames after
// the warm-up are timed, and left out of the frame statistics.
inline constexpr unsigned kWindowTimingInterval = 30;

// Rasteriser threads the main job gives lavapipe when LP_NUM_THREADS is unset (llvmpipe's own
// default is one per core); chosen by measurement on 2 cores (docs/play.md).
int default_lavapipe_threads();

// Both print the per-system CPU table and the per-pass GPU table; return main()'s status.
int run_headless(const Options& options);
int run_window(const Options& options);
int run_simulation_only(const Options& options);

}  // namespace penumbra::play
