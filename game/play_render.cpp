// The main job's loops: simulation only, headless (offscreen renderer, PNG screenshots) and
// windowed (swapchain + ImGui overlay). See play_main.cpp for the options.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <GLFW/glfw3.h>

#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/game/fixed_step.h"
#include "penumbra/game/probe_demo.h"
#include "penumbra/game/sample_render.h"
#include "penumbra/game/sample_world.h"
#include "penumbra/game/terrain_demo.h"
#include "penumbra/game/valley_game.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/jobs/frame_report.h"
#include "penumbra/render/image.h"
#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/overlay.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/window.h"
#include "penumbra/render/window_target.h"
#include "penumbra/systems/render_extract/render_extract.h"
#include "penumbra/systems/spherical_lights/spherical_light_systems.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_state.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"
#include "play.h"
#include "play_record.h"
#include "play_valley.h"
#include "tune/apply_settings.h"

namespace penumbra::play {
namespace {
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

bool write_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!(f << text)) return false;
  }
  return std::rename(tmp.c_str(), path.c_str()) == 0;  // atomic replace
}

// The sample world, its job graph and the CPU-side reports.
struct Sim {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor;
  jobs::TimingTable table;
  std::vector<jobs::FrameStats> traced;
  const Options& options;
  int warmup = 0;
  std::unique_ptr<ValleySession> valley;  // --scene valley

  Sim(const Options& o, bool with_render, bool window = false) : executor(o.threads), options(o) {
    executor.set_trace_tasks(!o.trace.empty());
    if (o.scene == "terrain" || o.scene == "valley") {
      const bool game = o.scene == "valley";
      game::TerrainDemoConfig demo;
      demo.data_dir = o.data;
      if (o.light_budget > 0) demo.light_refresh.budget = o.light_budget;
      if (o.boulders >= 0) demo.boulders.count = o.boulders;
      demo.boulders.show_spheres = o.show_spheres;
      if (o.boulder_detail >= 0) demo.boulders.simplify_error = o.boulder_detail;
      demo.probes.show = o.probes_debug;
      demo.follow_pair = o.follow_pair;
      if (o.probe_objects >= 0) demo.probes.count = o.probe_objects;
      demo.boulders.cache_dir = ((o.out.empty() ? std::string("build/play") : o.out) + "/spheres");
      demo.probes.cache_dir = ((o.out.empty() ? std::string("build/play") : o.out) + "/probes");
      // --settings: a tuned settings file (docs/tune.md), on the demo's config and resources.
      std::optional<tune::SystemSettings> tuned;
      if (!o.settings.empty()) tuned = tune::load_system_settings(o.settings);
      if (tuned) tune::apply_to_demo(*tuned, demo.shadow, demo.boulders.spheres, demo.probes.grid);
      if (game) demo = game::valley_world(demo);  // the game's lights, edits and camera
      game::populate_terrain_demo(world, demo);
      if (game) {
        game::populate_valley(world);
        valley = std::make_unique<ValleySession>(world, o, window);
        world.resource<game::HorizonProbe>().enabled = false;  // the horizon fan: demo only
      }
      if (tuned) tune::apply_to_world(*tuned, world);
      world.resource<game::HorizonProbe>().aspect =
          static_cast<float>(o.width) / static_cast<float>(o.height);
      game::add_terrain_demo_systems(schedule, demo);
      if (o.terrain_lod_pixels >= 0)
        world.resource<systems::RenderSettings>().view.terrain_lod_pixels = o.terrain_lod_pixels;
      world.resource<systems::RenderSettings>().environment.enabled = o.sun_shadows;
      return;
    }
    game::SampleWorldConfig config;
    config.particles = o.particles;
    game::populate_sample_world(world, config);
    game::add_sample_systems(schedule);
    if (with_render) {
      game::SampleSceneConfig scene;
      scene.max_points = o.points;
      game::populate_sample_scene(world, scene);
      game::add_sample_render_systems(schedule, scene);
    }
    executor.set_trace_tasks(!o.trace.empty());
  }

  // Light re-shading over the timed frames (terrain demo).
  std::size_t light_frames = 0, light_tiles_total = 0, light_tiles = 0;
  std::size_t light_observed = 0, light_visible = 0;
  double light_worst_observed = 0, light_worst_deferred = 0;
  // The turning environment's re-shading (environment_refresh.h), over the same frames.
  std::size_t environment_tiles_total = 0, environment_stale_total = 0;

  const jobs::FrameStats& step(int frame, int frames, GLFWwindow* window = nullptr) {
    if (valley) valley->before_step(world, static_cast<std::uint64_t>(frame), window);
    const jobs::FrameStats& stats = executor.run(schedule, world);
    if (frame >= warmup) {
      table.add(stats);
      // Between frames, outside the job graph: the system's state is safe to read here.
      world.query<const terrain_shadow::TerrainShadowState>().each(
          [&](const terrain_shadow::TerrainShadowState& x) {
            const terrain_shadow::LightRefreshStats& r = x.refresh.stats();
            ++light_frames;
            light_tiles = r.tiles;
            light_tiles_total += r.refreshed;
            light_observed += r.observed_texels;
            light_visible += r.observed_visible;
            light_worst_observed = std::max(light_worst_observed, double(r.worst_observed));
            light_worst_deferred = std::max(light_worst_deferred, double(r.worst_deferred));
            environment_tiles_total += x.environment_refresh.stats().refreshed;
            environment_stale_total += x.environment_refresh.stats().stale;
          });
    }
    if (!options.trace.empty() && frames > 0 && frame >= frames - 3) traced.push_back(stats);
    return stats;
  }

  // Prints the CPU table, writes the trace and the graph; false when a file cannot be written.
  bool report(int frames, const char* what) {
    std::printf("penumbra: %s, %zu entities, %d frames (%d warm-up), %d threads%s\n",
                options.scene == "valley"    ? "valley game"
                : options.scene == "terrain" ? "terrain demo"
                                             : "sample world",
                world.size(), frames, warmup, executor.threads(), what);
    if (const auto* bake = world.try_resource<game::ProbeSkyBake>(); bake && bake->bakes > 0)
      if (const auto* cloud = world.try_resource<components::ProbeCloudResource>();
          cloud && cloud->cloud)
        std::printf(
            "probes: %zu probes, %u tetrahedra, built at start-up in %.2f s (sky steps: %zu baked, "
            "%zu from the cache %s, %.2f s); sky step changes %llu (last %.2f ms)\n",
            cloud->cloud->probe_count(), cloud->cloud->inner_count, bake->startup_seconds,
            bake->steps_baked, bake->steps_loaded,
            bake->cache_folder.empty() ? "(none)" : bake->cache_folder.c_str(), bake->bake_seconds,
            static_cast<unsigned long long>(bake->bakes - 1), bake->last_bake_ms);
    table.print(std::cout);
    std::cout.flush();
    if (!options.trace.empty()) {
      if (!write_file(options.trace, jobs::chrome_trace_json(traced))) {
        std::fprintf(stderr, "penumbra_play: cannot write trace to %s\n", options.trace.c_str());
        return false;
      }
      std::printf("trace (Perfetto / chrome://tracing): %s\n", options.trace.c_str());
    }
    if (!options.dot.empty()) {
      if (!write_file(options.dot, schedule.to_dot())) {
        std::fprintf(stderr, "penumbra_play: cannot write graph to %s\n", options.dot.c_str());
        return false;
      }
      std::printf("job graph (Graphviz DOT): %s\n", options.dot.c_str());
    }
    return true;
  }
};

render::InstanceConfig instance_config(const Options& o) {
  render::InstanceConfig c;
  c.app_name = "penumbra_play";
  if (o.validation) c.validation = c.require_validation = true;
  return c;
}

std::string screenshot_path(const Options& o, const std::string& name) {
  std::filesystem::create_directories(o.out);
  return (std::filesystem::path(o.out) / name).string();
}

void print_frame_summary(const std::vector<FrameSample>& samples, int sim_threads) {
  if (samples.empty()) return;
  const FrameSummary s = summarize(samples);
  const char* lp = std::getenv("LP_NUM_THREADS");
  std::printf(
      "frame (wall): %.2f ms = %.1f fps, median %.2f, p95 %.2f  [simulation %.2f ms | render "
      "record+submit %.2f ms]  threads: simulation %d, lavapipe %s\n",
      s.mean_ms, s.fps, s.median_ms, s.p95_ms, s.sim_ms, s.render_ms, sim_threads,
      lp ? lp : "(default)");
}

// Frame times of an empty packet (clear + tonemap), the same-run baseline of --bench.
std::vector<FrameSample> empty_frames(render::Renderer& renderer, render::Target& target,
                                      int frames) {
  render::RenderPacket empty;
  empty.view.sky = empty.view.terrain = empty.view.meshes = empty.view.debug = false;
  std::vector<FrameSample> samples;
  for (int f = 0; f < frames + 5; ++f) {
    const auto t0 = Clock::now();
    renderer.render(empty, target);
    if (f >= 5) samples.push_back({ms_since(t0), 0, 0});
  }
  renderer.wait_idle();
  return samples;
}

// Other thread splits of the same run, as child processes; their JSON records.
std::vector<std::string> run_splits(const Options& o) {
  std::vector<std::string> records;
  std::size_t start = 0;
  while (start < o.bench_splits.size()) {
    std::size_t end = o.bench_splits.find(',', start);
    if (end == std::string::npos) end = o.bench_splits.size();
    const std::string split = o.bench_splits.substr(start, end - start);
    start = end + 1;
    int threads = 0, lp = 0;
    if (std::sscanf(split.c_str(), "%d:%d", &threads, &lp) != 2 || threads < 1 || lp < 0) {
      std::fprintf(stderr, "penumbra_play: --bench-splits needs T:L pairs, got '%s'\n",
                   split.c_str());
      continue;
    }
    const std::string file = o.bench + ".split";
    std::vector<std::string> args = {"--headless",
                                     "--screenshots",
                                     "0",
                                     "--scene",
                                     o.scene,
                                     "--frames",
                                     std::to_string(o.frames > 0 ? o.frames : 300),
                                     "--threads",
                                     std::to_string(threads),
                                     "--size",
                                     std::to_string(o.width) + "x" + std::to_string(o.height),
                                     "--bench",
                                     file};
    if (!o.data.empty()) args.insert(args.end(), {"--data", o.data});
    if (!o.device.empty()) args.insert(args.end(), {"--device", o.device});
    if (o.terrain_lod_pixels >= 0)
      args.insert(args.end(), {"--terrain-lod", std::to_string(o.terrain_lod_pixels)});
    if (o.light_budget > 0)
      args.insert(args.end(), {"--light-budget", std::to_string(o.light_budget)});
    if (o.probe_objects >= 0)
      args.insert(args.end(), {"--probe-objects", std::to_string(o.probe_objects)});
    if (o.sun_shadows) args.push_back("--sun-shadows");
    std::printf("penumbra: split %d simulation threads, LP_NUM_THREADS=%d\n", threads, lp);
    std::fflush(stdout);
    if (run_child(args, "LP_NUM_THREADS=" + std::to_string(lp)) != 0) {
      std::fprintf(stderr, "penumbra_play: split %s failed\n", split.c_str());
      continue;
    }
    std::ifstream in(file);
    records.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    std::filesystem::remove(file);
  }
  return records;
}
}  // namespace

int default_lavapipe_threads() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Frames of a headless run: --frames, else a replay's length, the autopilot's cap, or 300.
int headless_frames(const Options& o, const Sim& sim) {
  if (o.frames > 0) return o.frames;
  if (sim.valley && sim.valley->replay_steps() > 0)
    return static_cast<int>(sim.valley->replay_steps());
  return sim.valley ? kAutopilotFrameCap : 300;
}

int run_simulation_only(const Options& o) {
  Sim sim(o, /*with_render=*/false);
  int frames = headless_frames(o, sim);
  sim.warmup = frames > 10 ? 5 : 0;
  for (int f = 0; f < frames; ++f) {
    sim.step(f, frames);
    if (sim.valley && sim.valley->finished(static_cast<std::uint64_t>(f))) frames = f + 1;
  }
  if (!sim.report(frames, ", no renderer")) return 1;
  if (sim.valley) sim.valley->finish(sim.world);
  return 0;
}

int run_headless(const Options& o) {
  PlayRecord record;
  if (!o.bench.empty()) {
    describe_machine(record);  // the load average before the splits and this run add to it
    record.splits = run_splits(o);
  }
  Sim sim(o, /*with_render=*/true);
  int frames = headless_frames(o, sim);
  sim.warmup = frames > 10 ? 5 : 0;
  render::Instance instance(instance_config(o));
  render::DeviceConfig dc;
  dc.force = o.device;
  render::Device device(instance, dc);
  render::Renderer renderer(device);
  renderer.set_timing_interval(0);  // until the GPU-timed frames (below)
  render::OffscreenTarget target(static_cast<std::uint32_t>(o.width),
                                 static_cast<std::uint32_t>(o.height));
  std::unique_ptr<render::Overlay> hud;  // the game's HUD on its screenshots
  if (sim.valley && !o.out.empty() && o.screenshots > 0)
    hud = std::make_unique<render::Overlay>(
        device,
        VkExtent2D{static_cast<std::uint32_t>(o.width), static_cast<std::uint32_t>(o.height)});

  // Screenshot frames: spread from the first after warm-up to the last.
  std::vector<int> shots;
  if (!o.out.empty() && o.screenshots > 0) {
    const int k = o.screenshots;
    for (int i = 0; i < k; ++i)
      shots.push_back(k == 1 ? frames - 1 : sim.warmup + (frames - 1 - sim.warmup) * i / (k - 1));
  }
  // The baseline before and after the run (half each), so that a machine whose speed drifts
  // during the run moves the baseline with it.
  std::vector<FrameSample> baseline;
  if (!o.bench.empty()) baseline = empty_frames(renderer, target, o.empty_frames / 2);
  std::vector<std::string> written;
  std::vector<FrameSample> samples;
  double triangles = 0;
  // Frames [warm-up, timed_end) time their GPU passes and are not measured; later ones are
  // measured untimed (a timed frame on lavapipe flushes after every pass: gpu_timer.h).
  const int timed_end = sim.warmup + std::min(o.gpu_timing_frames, (frames - sim.warmup) / 2);
  for (int f = 0; f < frames; ++f) {
    if (f == sim.warmup) {
      renderer.wait_idle();
      renderer.pass_table().clear();
      renderer.set_timing_interval(1);
    }
    if (f == timed_end) {
      renderer.wait_idle();  // collects the last timed frames' pass times
      renderer.set_timing_interval(0);
    }
    const auto t0 = Clock::now();
    sim.step(f, frames);
    const double t_sim = ms_since(t0);
    const render::RenderPacket& packet = sim.world.resource<render::RenderPacket>();
    const auto t1 = Clock::now();
    if (std::find(shots.begin(), shots.end(), f) != shots.end()) {
      // The game's screenshots show its HUD (title, score, end screen) as the window does.
      render::Overlay* over = nullptr;
      if (hud) {
        render::OverlayStats s;
        s.panel = false;
        s.hud = sim.valley->hud(sim.world);
        render::ViewSettings view = packet.view;
        hud->build(s, view);  // twice: ImGui sizes an auto-resized window from its last frame
        hud->build(s, view);
        over = hud.get();
      }
      const auto image = renderer.capture(packet, target, over);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.png", f);
      if (image) {
        written.push_back(screenshot_path(o, name));
        render::write_png(written.back(), *image);
      }
      continue;  // a capture waits for the GPU: not a representative frame time
    }
    renderer.render(packet, target);
    if (f >= timed_end) {
      samples.push_back({ms_since(t0), t_sim, ms_since(t1)});
      triangles += static_cast<double>(renderer.stats().terrain_triangles);
    }
    if (sim.valley && sim.valley->finished(static_cast<std::uint64_t>(f))) frames = f + 1;
  }
  renderer.wait_idle();
  if (!o.bench.empty()) {
    record.empty_frame_before_ms = summarize(baseline).median_ms;
    const std::vector<FrameSample> after = empty_frames(renderer, target, o.empty_frames / 2);
    record.empty_frame_after_ms = summarize(after).median_ms;
    baseline.insert(baseline.end(), after.begin(), after.end());
    record.empty_frame_ms = summarize(baseline).median_ms;  // the demo frames' median definition
    // The last frame at the scene's level of detail and at full detail, compared.
    render::RenderPacket packet = sim.world.resource<render::RenderPacket>();
    const auto lod = renderer.capture(packet, target);
    packet.view.terrain_lod_pixels = 0;
    const auto full = renderer.capture(packet, target);
    record.terrain_triangles_full = renderer.stats().terrain_triangles;
    if (lod && full) {
      const render::ImageComparison c = render::compare_images(*lod, *full, 24);
      record.lod_differing_fraction = c.fraction();
      record.lod_max_difference = c.max_difference;
    }
    record.terrain_lod_pixels = sim.world.resource<render::RenderPacket>().view.terrain_lod_pixels;
  }
  const std::string what = ", renderer: " + device.name() + " " + std::to_string(o.width) + "x" +
                           std::to_string(o.height) + " offscreen";
  if (!sim.report(frames, what.c_str())) return 1;
  renderer.pass_table().print(std::cout);
  print_frame_summary(samples, sim.executor.threads());
  const auto stats = renderer.stats();
  std::printf("drawn per frame: %.0f terrain + %llu mesh triangles, %zu points; upload %.2f MiB\n",
              samples.empty() ? 0.0 : triangles / static_cast<double>(samples.size()),
              static_cast<unsigned long long>(stats.mesh_triangles),
              sim.world.resource<render::RenderPacket>().points.size(),
              static_cast<double>(stats.uploaded) / (1 << 20));
  if (sim.light_frames > 0)
    std::printf(
        "lights: %.1f of %zu tiles re-shaded per frame; of the texels re-shaded, %.1f%% had "
        "changed by more than the tolerance while waiting (at most %.0f%% of their "
        "irradiance)\n",
        static_cast<double>(sim.light_tiles_total) / sim.light_frames, sim.light_tiles,
        sim.light_observed ? 100.0 * sim.light_visible / sim.light_observed : 0.0,
        100.0 * sim.light_worst_observed);
  for (const std::string& p : written) std::printf("screenshot: %s\n", p.c_str());
  if (sim.valley) sim.valley->finish(sim.world);
  if (instance.validation()) std::printf("validation: %s\n", instance.messages().summary().c_str());
  if (!o.bench.empty()) {
    record.scene = o.scene;
    record.device = device.name();
    record.width = o.width;
    record.height = o.height;
    record.frames = frames;
    record.warmup = sim.warmup;
    record.sim_threads = sim.executor.threads();
    const char* lp = std::getenv("LP_NUM_THREADS");
    record.lavapipe_threads = lp ? lp : "";
    record.samples = samples;
    for (const render::PassTimingTable::Row& row : renderer.pass_table().rows())
      record.gpu_pass_ms[row.name] = renderer.pass_table().mean_ms(row.name);
    record.gpu_frame_ms = renderer.pass_table().mean_total_ms();
    record.gpu_timed_frames = static_cast<int>(renderer.pass_table().frames());
    record.terrain_triangles = samples.empty() ? 0 : triangles / samples.size();
    record.light_tiles = sim.light_tiles;
    if (sim.light_frames > 0)
      record.light_tiles_per_frame = static_cast<double>(sim.light_tiles_total) / sim.light_frames;
    record.light_worst_observed = sim.light_worst_observed;
    record.light_visible_fraction =
        sim.light_observed ? static_cast<double>(sim.light_visible) / sim.light_observed : 0.0;
    if (sim.light_frames > 0) {
      record.environment_tiles_per_frame =
          static_cast<double>(sim.environment_tiles_total) / sim.light_frames;
      record.environment_stale_per_frame =
          static_cast<double>(sim.environment_stale_total) / sim.light_frames;
    }
    record.light_worst_deferred = sim.light_worst_deferred;
    const std::size_t n = sim.table.frames();
    for (const jobs::TimingTable::Row& row : sim.table.rows())
      if (!row.sync)
        record.systems.push_back({row.name, n ? row.total_ms / static_cast<double>(n) : 0.0,
                                  row.max_ms, row.reported, row.done_per_frame(n),
                                  row.skipped_per_frame(n)});
    std::filesystem::path out(o.bench);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    if (!write_file(o.bench, to_json(record))) {
      std::fprintf(stderr, "penumbra_play: cannot write %s\n", o.bench.c_str());
      return 1;
    }
    std::printf("bench record: %s\n", o.bench.c_str());
  }
  return 0;
}

int run_window(const Options& o) {
  Sim sim(o, /*with_render=*/true, /*window=*/true);
  sim.warmup = 5;
  render::Glfw glfw;
  render::InstanceConfig ic = instance_config(o);
  ic.extensions = glfw.instance_extensions();
  render::Instance instance(ic);
  render::Window window(glfw, instance, o.width, o.height, "penumbra");
  render::DeviceConfig dc;
  dc.force = o.device;
  dc.present_surface = window.surface();
  render::Device device(instance, dc);
  render::WindowTarget target(device, window, render::Renderer::kFramesInFlight,
                              /*vsync=*/false);
  render::Renderer renderer(device);
  renderer.set_timing_interval(kWindowTimingInterval);
  render::Overlay overlay(device, window);
  systems::RenderSettings& settings = sim.world.resource<systems::RenderSettings>();

  render::OverlayStats stats;
  stats.device = device.name();
  std::vector<FrameSample> samples;
  int f = 0;
  auto last = Clock::now();
  game::FixedStepClock clock(game::kDemoStepSeconds);  // the game runs in real time
  int step = 0;
  bool p_was_down = false, i_was_down = false, c_was_down = false, f1_was_down = false;
  stats.panel = !sim.valley;  // the game starts with its HUD alone (F1: the panel)
  for (; !window.should_close() && (o.frames == 0 || f < o.frames); ++f) {
    window.poll_events();
    if (window.escape_pressed()) window.request_close();
    // P toggles the probe cloud's debug views (probe_demo.h), on the key's press.
    const bool p_down = !sim.valley && glfwGetKey(window.glfw(), GLFW_KEY_P) == GLFW_PRESS;
    if (p_down && !p_was_down)
      if (auto* view = sim.world.try_resource<game::ProbeDebugView>())
        view->enabled = !view->enabled;
    p_was_down = p_down;
    // I toggles the spherical lights' indirect light (systems/spherical_lights).
    const bool i_down = glfwGetKey(window.glfw(), GLFW_KEY_I) == GLFW_PRESS;
    auto* sl = sim.world.try_resource<spherical_lights::SphericalLightSettingsResource>();
    if (i_down && !i_was_down && sl) sl->indirect = !sl->indirect;
    i_was_down = i_down;
    // C toggles the camera between the orbit and the boulder pair.
    const bool c_down = glfwGetKey(window.glfw(), GLFW_KEY_C) == GLFW_PRESS;
    auto* cam = sim.world.try_resource<game::DemoCameraMode>();
    if (c_down && !c_was_down && cam && !sim.valley) cam->follow_pair = !cam->follow_pair;
    c_was_down = c_down;
    stats.lines.clear();
    // F1 toggles the panel (systems, passes, view switches); the game's HUD stays.
    const bool f1_down = glfwGetKey(window.glfw(), GLFW_KEY_F1) == GLFW_PRESS;
    if (f1_down && !f1_was_down) stats.panel = !stats.panel;
    f1_was_down = f1_down;
    if (sim.valley) stats.hud = sim.valley->hud(sim.world);
    if (sl)
      stats.lines.push_back(std::string("I: indirect light ") + (sl->indirect ? "on" : "off"));
    if (cam && !sim.valley)
      stats.lines.push_back(std::string("C: camera ") +
                            (cam->follow_pair ? "on the pair" : "orbit"));
    if (auto* probe = sim.world.try_resource<game::HorizonProbe>()) {
      // The horizon debug view follows the cursor (window coordinates to NDC, y down).
      double cx = 0, cy = 0;
      int ww = 1, wh = 1;
      glfwGetCursorPos(window.glfw(), &cx, &cy);
      glfwGetWindowSize(window.glfw(), &ww, &wh);
      if (ww > 0 && wh > 0) {
        probe->ndc = {2.0f * static_cast<float>(cx) / ww - 1.0f,
                      2.0f * static_cast<float>(cy) / wh - 1.0f};
        probe->aspect = static_cast<float>(ww) / static_cast<float>(wh);
      }
    }
    if (f == sim.warmup) renderer.pass_table().clear();
    const auto t0 = Clock::now();
    // The game: as many fixed steps as the wall clock owes (fixed_step.h); the other scenes
    // one step a frame.
    const int steps =
        sim.valley ? clock.steps(std::chrono::duration<double>(t0 - last).count()) : 1;
    for (int k = 0; k < steps; ++k) sim.step(step++, o.frames, window.glfw());
    const jobs::FrameStats& frame = sim.executor.last_frame();
    const double t_sim = ms_since(t0);
    stats.frame_ms = std::chrono::duration<double, std::milli>(t0 - last).count();
    last = t0;
    stats.systems.clear();
    for (const jobs::SystemTiming& s : frame.systems)
      if (!s.sync)
        stats.systems.push_back({std::string(s.name), 1e-6 * static_cast<double>(s.duration_ns),
                                 s.reported, s.done, s.skipped, /*pausable=*/true,
                                 sim.schedule.paused(s.name)});
    stats.passes = renderer.last_pass_times();
    overlay.build(stats, settings.view);
    // The panel's checkboxes freeze and resume systems from the next frame on.
    for (const render::OverlaySystem& s : stats.systems)
      if (s.paused != sim.schedule.paused(s.name)) sim.schedule.set_paused(s.name, s.paused);
    // The overlay's toggles apply to this frame already: a copy of the packet with them (the
    // extract stays the packet's only writer).
    render::RenderPacket packet = sim.world.resource<render::RenderPacket>();
    packet.view = settings.view;
    const auto t1 = Clock::now();
    renderer.render(packet, target, {false, &overlay});
    if (f >= sim.warmup) samples.push_back({ms_since(t0), t_sim, ms_since(t1)});
  }
  std::string shot;
  if (!o.out.empty()) {
    const render::RenderPacket& packet = sim.world.resource<render::RenderPacket>();
    overlay.build(stats, settings.view);
    if (const auto image = renderer.capture(packet, target, &overlay)) {
      shot = screenshot_path(o, "window.png");
      render::write_png(shot, *image);
    }
  }
  renderer.wait_idle();
  const std::string what = ", renderer: " + device.name() + " window";
  if (!sim.report(f, what.c_str())) return 1;
  if (sim.valley) sim.valley->finish(sim.world);
  renderer.pass_table().print(std::cout);
  print_frame_summary(samples, sim.executor.threads());
  if (!shot.empty()) std::printf("screenshot: %s\n", shot.c_str());
  return 0;
}

}  // namespace penumbra::play
