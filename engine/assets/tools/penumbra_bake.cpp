// ./penumbra bake SCENE.json -o FILE.pcld: bakes a probe cloud for a scene description
// (systems/probe_bake, issue 14; docs/probe_bake.md): uniform grid placement, irradiance capture
// with one bounce by the reference ray tracer, validity (virtual offset, dilation), Delaunay
// build, then the atomic write of probe_cloud_file.h (a temporary file renamed over the target:
// an interrupted bake leaves the old file intact). A progress bar with an ETA goes to stderr,
// the summary to stdout. Exit 1 on a scene, bake or write error (the message names the file),
// 2 on bad arguments. The same inputs give the same bytes, for any thread count.
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include <tbb/global_control.h>

#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/systems/probe_bake/probe_bake.h"

namespace {

using namespace penumbra;

constexpr const char* kUsage =
    "usage: penumbra_bake SCENE.json -o FILE.pcld [--spacing M] [--samples N] [--bands N]\n"
    "                     [--seed N] [--no-validity] [--one-sided] [--no-bounce] [--threads N]\n"
    "                     [--method grid|spawn-merge|gradient] [--max-probes N]\n"
    "                     [--edge-rays] [--edge-rounds N] [--data DIR]\n"
    "  --method: placement ([Sukys14] sec. 3.1; default grid); --max-probes: spawn-merge's cap\n"
    "  --edge-rays: probes where Delaunay edges cross geometry ([Sukys14] sec. 3.2.2)\n"
    "  --edge-rounds N: edge-ray rounds (default 3; implies --edge-rays)\n"
    "  --data DIR: where the scene's files live (default: SCENE's folder/../../shared/data)\n";

int usage(const std::string& why) {
  std::fprintf(stderr, "penumbra_bake: %s\n%s", why.c_str(), kUsage);
  return 2;
}

template <class T>
bool parse_number(std::string_view s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

// A 40-column bar with the probes done and an ETA from the rate so far.
class ProgressBar {
 public:
  void operator()(std::size_t done, std::size_t total) {
    const double f = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = f > 0 ? elapsed * (1 - f) / f : 0.0;
    char bar[41];
    const int filled = static_cast<int>(f * 40);
    for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : '-';
    bar[40] = '\0';
    std::fprintf(stderr, "\r  [%s] %3d%%  %zu/%zu probes  %.1f s  ETA %.1f s   ", bar,
                 static_cast<int>(f * 100), done, total, elapsed, eta);
    std::fflush(stderr);
    shown_ = true;
  }
  void done() const {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  bool shown_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path scene_path, out_path, data_dir;
  probe_bake::BakeSettings s;
  int threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    auto take = [&] { ++i; };
    if (a == "-o") {
      if (v == nullptr) return usage("-o needs a file name");
      out_path = v, take();
    } else if (a == "--data") {
      if (v == nullptr) return usage("--data needs a folder");
      data_dir = v, take();
    } else if (a == "--spacing") {
      if (v == nullptr || !parse_number(v, s.spacing) || !(s.spacing > 0) ||
          !std::isfinite(s.spacing))
        return usage("--spacing needs a finite number > 0 (metres)");
      take();
    } else if (a == "--samples") {
      if (v == nullptr || !parse_number(v, s.samples) || s.samples < 2)
        return usage("--samples needs an integer >= 2");
      take();
    } else if (a == "--bands") {
      if (v == nullptr || !parse_number(v, s.bands) || s.bands < 2 || s.bands > 4)
        return usage("--bands needs an integer in 2..4");
      take();
    } else if (a == "--seed") {
      if (v == nullptr || !parse_number(v, s.seed)) return usage("--seed needs an integer");
      take();
    } else if (a == "--threads") {
      if (v == nullptr || !parse_number(v, threads) || threads < 1)
        return usage("--threads needs an integer >= 1");
      take();
    } else if (a == "--no-validity") {
      s.validity = false;
    } else if (a == "--one-sided") {
      s.validity_settings.both_sides = false;
    } else if (a == "--no-bounce") {
      s.bounce = false;
    } else if (a == "--method") {
      const std::string_view m = v ? v : "";
      if (m == "grid") {
        s.placement = probe_bake::PlacementMethod::kGrid;
      } else if (m == "spawn-merge") {
        s.placement = probe_bake::PlacementMethod::kSpawnMerge;
      } else if (m == "gradient") {
        s.placement = probe_bake::PlacementMethod::kGradient;
      } else {
        return usage("--method needs grid, spawn-merge or gradient");
      }
      take();
    } else if (a == "--max-probes") {
      if (v == nullptr || !parse_number(v, s.spawn_merge.max_probes) ||
          s.spawn_merge.max_probes < 1)
        return usage("--max-probes needs an integer >= 1");
      take();
    } else if (a == "--edge-rays") {
      s.edge_rays.enabled = true;
    } else if (a == "--edge-rounds") {
      if (v == nullptr || !parse_number(v, s.edge_rays.max_iterations) ||
          s.edge_rays.max_iterations < 1)
        return usage("--edge-rounds needs an integer >= 1");
      s.edge_rays.enabled = true;
      take();
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + std::string(a));
    } else {
      if (!scene_path.empty()) return usage("more than one scene file");
      scene_path = a;
    }
  }
  if (scene_path.empty()) return usage("no scene file");
  if (out_path.empty()) return usage("no output file (-o FILE.pcld)");
  if (data_dir.empty()) data_dir = scene_path.parent_path() / ".." / ".." / "shared" / "data";
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(threads));
  try {
    const probe_bake::BakeScene scene = probe_bake::load_bake_scene(scene_path, data_dir);
    probe_bake::BakeReport r;
    ProgressBar bar;
    const data::ProbeCloud cloud = probe_bake::bake_probe_cloud(scene, s, &r, std::ref(bar));
    bar.done();
    if (!r.valid_cloud) {
      std::fprintf(stderr, "penumbra_bake: %s: the baked cloud failed validation:\n",
                   scene_path.string().c_str());
      for (const std::string& e : r.validation_errors) std::fprintf(stderr, "  %s\n", e.c_str());
      return 1;
    }
    assets::save_probe_cloud_file(out_path, cloud);
    const std::size_t placed = r.placed;
    std::printf("scene            %s (%s)\n", scene.name.c_str(), scene_path.string().c_str());
    for (const std::string& note : scene.notes) std::printf("note             %s\n", note.c_str());
    const char* method = s.placement == probe_bake::PlacementMethod::kGrid         ? "grid"
                         : s.placement == probe_bake::PlacementMethod::kSpawnMerge ? "spawn-merge"
                                                                                   : "gradient";
    std::printf("placement        %s, spacing %g m\n", method,
                static_cast<double>(s.spacing > 0 ? s.spacing : scene.volume.spacing));
    if (s.placement != probe_bake::PlacementMethod::kGrid) {
      const auto& a = r.adaptive;
      const char* stop[] = {"no change", "iteration cap", "probe cap", "small steps"};
      std::printf(
          "adaptive         %zu initial -> %zu; %d iterations (stop: %s); %zu spawned, %zu "
          "merged, %zu moves, %zu reverted, %zu black -> %zu clusters; %zu captures, %.2f s\n",
          a.initial, placed, a.iterations, stop[static_cast<int>(a.stop)], a.spawned, a.merged,
          a.moves, a.reverted, a.black, a.clusters, a.captured, r.placement_seconds);
    }
    std::printf("probes           %zu placed, %zu in the cloud, %d bands\n", placed,
                cloud.probe_count(), cloud.bands);
    std::printf("validity         %zu valid, %zu offset, %zu dilated, %zu black, %zu split%s\n",
                r.valid, r.offset, r.dilated, r.black, r.split,
                s.validity ? "" : " (validity off)");
    if (s.edge_rays.enabled)
      std::printf(
          "edge rays        %zu added, %zu dropped (invalid), %d rounds; %zu edges, %zu hits "
          "(%zu grazing, %zu near a vertex, %zu blocked, %zu crowded)\n",
          r.edge_added, r.edge_dropped, r.edge_rounds, r.edge.edges, r.edge.hits, r.edge.grazing,
          r.edge.near_vertex, r.edge.blocked, r.edge.crowded);
    std::printf("samples          %d per probe, seed %llu, bounce %s\n", s.samples,
                static_cast<unsigned long long>(s.seed), s.bounce ? "on" : "off");
    std::printf("std error        %.2f%% mean, %.2f%% max (irradiance DC, relative)\n",
                100 * r.mean_rel_std_error, 100 * r.max_rel_std_error);
    std::printf(
        "rays             %llu (%.0f per probe, %.2f M/s)\n",
        static_cast<unsigned long long>(r.rays),
        placed ? static_cast<double>(r.rays) / static_cast<double>(placed) : 0.0,
        r.capture_seconds > 0 ? static_cast<double>(r.rays) / r.capture_seconds / 1e6 : 0.0);
    std::printf(
        "tetrahedra       %u inner, %zu outer cells (%zu merged probes, %zu coordinates "
        "snapped to the box's faces)\n",
        cloud.inner_count, cloud.cells.size() - cloud.inner_count, r.merged, r.snapped);
    std::printf(
        "time             %.2f s (capture %.2f, validity %.2f, edge rays %.2f, build %.3f)\n",
        r.total_seconds, r.capture_seconds, r.validity_seconds, r.edge_seconds, r.build_seconds);
    std::printf("wrote            %s\n", out_path.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\npenumbra_bake: %s\n", e.what());
    return 1;
  }
  return 0;
}
