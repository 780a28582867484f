// The main job: the terrain demo (or the sample world) through the job graph and the Vulkan
// renderer.
//
//   penumbra_play [--scene valley|terrain|sample] [--input FILE] [--record FILE] [--autopilot]
//                 [--data DIR] [--frames N] [--threads T] [--particles N]
//   [--trace FILE] [--dot FILE]
//                 [--out DIR] [--screenshots K] [--headless] [--no-render] [--validation]
//                 [--device NAME] [--size WxH] [--points N] [--boulders N] [--boulder-detail E]
//                 [--show-spheres] [--probe-objects N] [--probes-debug] [--follow-pair]
//                 [--terrain-lod PX]
//                 [--light-budget F] [--sun-shadows]
//                 [--bench FILE [--bench-splits T:L,...]] [--gpu-timing-frames N]
//                 [--settings FILE]
//
// --settings FILE: a tuned settings file (./penumbra tune, docs/tune.md) applied to the systems'
// settings resources and the demo (terrain horizons and azimuths, blocker epsilon, spheres per
// boulder, probes per side); a bad file is an error naming it and the reason (exit 1).
// --scene valley (default): the game (valley_game.h, docs/game.md). Headless it replays a
// recorded session (--input FILE; default game/sessions/dusk_run.pinput) to its end, or lets
// the scripted player play (--autopilot) until the round ends; --record FILE writes the
// session's input (window, autopilot or replay) as a recording. In a window the devices drive it.
// --scene terrain: the elevation model lit by the terrain shadow system under a
// rotating HDR sky, a moving spherical light and periodic brush edits (terrain_demo.h);
// --scene sample: the particle sample world. --data DIR overrides ../shared/data.
// With a display ($DISPLAY / $WAYLAND_DISPLAY) and no --headless: a window with the ImGui
// overlay, until it is closed (or N frames). Otherwise offscreen: N frames (default 300), K
// screenshots written to DIR as PNG. Both print the per-system CPU timing table and the
// per-pass GPU timing table. --points N draws at most N particles (every k-th; 0: all).
// --boulder-detail E: the boulders' meshes simplified to relative error E (0: full meshes).
// --probe-objects N: the objects lit by the probe cloud (0: no cloud); --probes-debug starts
// with its debug views on (probes, each object's cell and walk; key P toggles them in the
// window). --follow-pair starts with the camera on the red and white boulders whose spherical
// lights bleed colour onto each other and the ground (key C toggles; key I the indirect light).
// --terrain-lod PX overrides the terrain's pixel budget (0: full detail); --light-budget F
// the largest fraction of the terrain a light re-shades per frame (light_refresh.h).
// --sun-shadows: the meshes shaded per pixel from the map's detected sources, each with a
// shadow map, and their OEMs (render::EnvironmentShading; docs/environment.md). --bench FILE
// (headless) also writes the run's record as JSON (play_record.h), with an empty-frame baseline
// and the image against full detail; --bench-splits runs the same scene again per thread split
// (T simulation threads, L = LP_NUM_THREADS) first and includes those records. Headless, the
// GPU passes are timed over the N frames after the warm-up (--gpu-timing-frames, default 40,
// at most half the rest), which the frame statistics leave out.
// Threads: --threads T for the job graph (0, the default: one per core); LP_NUM_THREADS, when
// unset, is set by play::default_lavapipe_threads() before the renderer starts (play.h).
#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "penumbra/assets/load_error.h"
#include "penumbra/render/window.h"
#include "penumbra/settings/tuned_settings.h"
#include "play.h"

namespace {
using penumbra::play::Options;

[[noreturn]] void usage(const char* error) {
  std::fprintf(
      stderr,
      "penumbra_play: %s\nusage: penumbra_play [--scene valley|terrain|sample] [--input FILE] "
      "[--record FILE] [--autopilot] [--data DIR] "
      "[--frames N] [--threads T] "
      "[--particles N] [--trace FILE] [--dot FILE] [--out DIR] [--screenshots K] "
      "[--headless] [--no-render] [--validation] [--device NAME] [--size WxH] "
      "[--points N] [--boulders N] [--boulder-detail E] [--show-spheres] [--probe-objects N] "
      "[--probes-debug] [--follow-pair] [--terrain-lod PX] "
      "[--light-budget F] [--sun-shadows] "
      "[--bench FILE "
      "[--bench-splits "
      "T:L,...]] [--gpu-timing-frames N] [--settings FILE]\n",
      error);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    auto number = [&](long lo) {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0' || n < lo)
        usage((a + " needs an integer >= " + std::to_string(lo) + ", got '" + v + "'").c_str());
      return n;
    };
    if (a == "--scene") {
      o.scene = value();
      if (o.scene != "valley" && o.scene != "terrain" && o.scene != "sample")
        usage(("--scene needs valley, terrain or sample, got '" + o.scene + "'").c_str());
    } else if (a == "--input")
      o.input = value();
    else if (a == "--record")
      o.record = value();
    else if (a == "--autopilot")
      o.autopilot = true;
    else if (a == "--data")
      o.data = value();
    else if (a == "--frames")
      o.frames = static_cast<int>(number(1));
    else if (a == "--threads")
      o.threads = static_cast<int>(number(0));
    else if (a == "--particles")
      o.particles = static_cast<std::size_t>(number(0));
    else if (a == "--trace")
      o.trace = value();
    else if (a == "--dot")
      o.dot = value();
    else if (a == "--out")
      o.out = value();
    else if (a == "--screenshots")
      o.screenshots = static_cast<int>(number(0));
    else if (a == "--headless")
      o.headless = true;
    else if (a == "--no-render")
      o.render = false;
    else if (a == "--validation")
      o.validation = true;
    else if (a == "--points")
      o.points = static_cast<std::size_t>(number(0));
    else if (a == "--show-spheres")
      o.show_spheres = true;
    else if (a == "--sun-shadows")
      o.sun_shadows = true;
    else if (a == "--probes-debug")
      o.probes_debug = true;
    else if (a == "--follow-pair")
      o.follow_pair = true;
    else if (a == "--probe-objects")
      o.probe_objects = static_cast<int>(number(0));
    else if (a == "--boulders")
      o.boulders = static_cast<int>(number(0));
    else if (a == "--boulder-detail") {
      const std::string v = value();
      char* end = nullptr;
      o.boulder_detail = std::strtof(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(o.boulder_detail >= 0 && o.boulder_detail < 1))
        usage(("--boulder-detail needs a relative error in [0, 1), got '" + v + "'").c_str());
    } else if (a == "--terrain-lod") {
      const std::string v = value();
      char* end = nullptr;
      o.terrain_lod_pixels = std::strtof(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(o.terrain_lod_pixels >= 0))
        usage(("--terrain-lod needs pixels >= 0, got '" + v + "'").c_str());
    } else if (a == "--light-budget") {
      const std::string v = value();
      char* end = nullptr;
      o.light_budget = std::strtof(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(o.light_budget > 0 && o.light_budget <= 1))
        usage(("--light-budget needs a fraction in (0, 1], got '" + v + "'").c_str());
    } else if (a == "--bench")
      o.bench = value();
    else if (a == "--bench-splits")
      o.bench_splits = value();
    else if (a == "--settings")
      o.settings = value();
    else if (a == "--gpu-timing-frames")
      o.gpu_timing_frames = static_cast<int>(number(0));
    else if (a == "--device")
      o.device = value();
    else if (a == "--size") {
      const std::string v = value();
      if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 || o.height < 1)
        usage(("--size needs WxH, got '" + v + "'").c_str());
    } else {
      usage(("unknown option " + a).c_str());
    }
  }
  return o;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace penumbra;
  Options opt = parse(argc, argv);
  if (!opt.settings.empty()) {  // a bad settings file fails before anything starts
    try {
      settings::load_settings(opt.settings);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "penumbra_play: --settings: %s\n", e.what());
      return 1;
    }
  }
  // Per-frame arrays (lighting, ratios, copies for the packet) are 0.1-1 MB. Left to glibc's
  // adaptive threshold, whole runs sometimes served them by mmap: fresh pages every frame, 20%
  // of the time in page faults and 3x slower frames (docs/play.md). Keep them on the heap.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  // llvmpipe reads LP_NUM_THREADS when the device is created: the CPU split (docs/play.md).
  if (!std::getenv("LP_NUM_THREADS"))
    setenv("LP_NUM_THREADS", std::to_string(play::default_lavapipe_threads()).c_str(), 0);
  try {
    if (!opt.render) return play::run_simulation_only(opt);
    if (!opt.headless && render::Glfw::display_available()) return play::run_window(opt);
    return play::run_headless(opt);
  } catch (const assets::LoadError& e) {  // a bad input file: its name and the reason
    std::fprintf(stderr, "penumbra_play: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_play: %s\n", e.what());
    if (opt.render)
      std::fprintf(stderr, "(no usable Vulkan device? --no-render runs the simulation only)\n");
    return 1;
  }
}
