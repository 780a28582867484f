// ./penumbra tune SCENE --budget B [-o FILE] [--data DIR] [--samples N] [--trace]: per lighting
// system the cheapest configuration whose relative RMS error against the reference stays within
// B on the scene (game/tune/tune.h, greedy_search.h; docs/tune.md), written as a settings file
// (tuned_settings.h; default build/tune/<scene>.settings). A progress bar on stderr, the table
// on stdout (--trace: every evaluation too). Exit 1 with the loader's message on a bad scene,
// 2 on bad arguments.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "penumbra/settings/tuned_settings.h"
#include "tune/tune.h"

namespace {

[[noreturn]] void usage(const std::string& error) {
  std::fprintf(stderr,
               "penumbra_tune: %s\nusage: penumbra_tune SCENE.json --budget B [-o FILE] "
               "[--data DIR] [--samples N] [--trace]\n",
               error.c_str());
  std::exit(2);
}

void print_row(const char* system, const std::string& config,
               const penumbra::settings::TuneResult& r) {
  std::printf("%-17s %-46s %7.2f%% %-4s %9.2f ms %4d / %-4d\n", system, config.c_str(),
              100 * r.error, r.met ? "ok" : "MISS", r.ms, r.evaluations, r.grid);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace penumbra;
  std::string scene_path, out, data = PENUMBRA_SHARED_DATA;
  double budget = -1;
  bool trace = false;  // every evaluation on stdout
  tune::TuneOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage("missing value after " + a);
      return argv[++i];
    };
    if (a == "--budget") {
      const std::string v = value();
      char* end = nullptr;
      budget = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(budget > 0 && budget < 1))
        usage("--budget needs a relative error in (0, 1), got '" + v + "'");
    } else if (a == "-o") {
      out = value();
    } else if (a == "--data") {
      data = value();
    } else if (a == "--trace") {
      trace = true;
    } else if (a == "--samples") {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0' || n < 16 || n > 1 << 20)
        usage("--samples needs an integer in [16, 2^20], got '" + v + "'");
      options.reference_samples = static_cast<int>(n);
    } else if (!a.empty() && a[0] == '-') {
      usage("unknown option " + a);
    } else if (scene_path.empty()) {
      scene_path = a;
    } else {
      usage("more than one scene");
    }
  }
  if (scene_path.empty()) usage("no scene");
  if (budget < 0) usage("no --budget");
  try {
    const tune::TuneScene scene = tune::load_tune_scene(scene_path, data);
    if (out.empty()) {
      std::filesystem::create_directories("build/tune");
      out = "build/tune/" + scene.name + ".settings";
    }
    std::string current;
    const auto progress = [&](const tune::ProgressEvent& ev) {
      if (ev.reference) {
        if (!current.empty()) std::fprintf(stderr, "\n");
        current = ev.system;
        std::fprintf(stderr, "%-9s computing the reference...", ev.system.c_str());
        return;
      }
      if (trace)
        std::printf("  %-9s %-46s error %7.3f%%  cost %10.3f  %9.2f ms\n", ev.system.c_str(),
                    ev.config.c_str(), 100 * ev.eval.error, ev.eval.cost, ev.eval.ms);
      constexpr int kWidth = 30;
      const int filled = ev.grid > 0 ? kWidth * ev.evaluations / ev.grid : 0;
      std::fprintf(stderr, "\r%-9s [%s%s] %d evaluated (grid %d)          ", ev.system.c_str(),
                   std::string(static_cast<std::size_t>(filled), '#').c_str(),
                   std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(),
                   ev.evaluations, ev.grid);
    };
    const settings::TunedSettings s = tune::run_tune(scene, budget, options, progress);
    std::fprintf(stderr, "\n");
    settings::save_settings(out, s);
    std::printf("scene %s, budget %.2f%% (relative RMS error against the reference)\n",
                scene.name.c_str(), 100 * budget);
    std::printf("%-17s %-46s %8s %-4s %12s %s\n", "system", "chosen configuration", "error", "",
                "time", "evaluated / grid");
    const settings::TerrainTuning& t = s.terrain;
    print_row("terrain",
              "horizon " + t.horizon +
                  (t.horizon == "march" ? " ls " + std::to_string(t.level_step) : "") + ", n_phi " +
                  std::to_string(t.azimuths) + ", " + std::to_string(t.bands) + " bands",
              t.result);
    char eps[32];
    std::snprintf(eps, sizeof eps, "%.2f", s.blockers.epsilon);
    print_row("blockers",
              std::to_string(s.blockers.spheres_per_object) + " spheres/object, eps " + eps + ", " +
                  std::to_string(s.blockers.bands) + " bands",
              s.blockers.result);
    char sp[64];
    std::snprintf(sp, sizeof sp, "%d per side (%.1f m), ", s.probes.probes_per_side,
                  s.probes.spacing);
    print_row("probes", sp + s.probes.placement, s.probes.result);
    const settings::SphericalLightTuning& l = s.spherical_lights;
    print_row("spherical_lights",
              std::to_string(10 * l.directions_frequency * l.directions_frequency + 2) +
                  " directions, " + l.blocking + ", " + l.horizon,
              l.result);
    std::printf("settings -> %s\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\npenumbra_tune: %s\n", e.what());
    return 1;
  }
  return 0;
}
