// penumbra_spheres MODEL.glb -n N -o FILE [--method kmeans|variational] [--seed S]
//                  [--surface-samples S] [--volume-cells V] [--iterations I]
// (./penumbra spheres): fits N spheres to every mesh of a glTF model (sphere_fit.h), prints the
// fit's figures (Er, surface coverage, time) and writes them with the set to a sphere file
// (sphere_file.h). A progress bar goes to stderr. Exit 1 on a load, fit or write error (the
// message names the file and the reason), 2 on bad arguments.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include "penumbra/assets/gltf.h"
#include "penumbra/assets/sphere_file.h"
#include "penumbra/assets/sphere_fit.h"

namespace {

using namespace penumbra;

constexpr const char* kUsage =
    "usage: penumbra_spheres MODEL.glb -n N -o FILE.psph [--method kmeans|variational] "
    "[--seed S]\n"
    "       [--surface-samples S] [--volume-cells V] [--iterations I]  (sphere_fit.h)\n";

int usage(const std::string& why) {
  std::fprintf(stderr, "penumbra_spheres: %s\n%s", why.c_str(), kUsage);
  return 2;
}

template <class T>
bool parse_number(std::string_view s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

// A 40-column bar redrawn in place whenever the percentage or the stage changes.
class ProgressBar {
 public:
  void operator()(double f, std::string_view stage) {
    const int pct = static_cast<int>(f * 100.0);
    if (pct == pct_ && stage == stage_) return;
    pct_ = pct;
    stage_ = stage;
    char bar[41];
    const int filled = pct * 40 / 100;
    for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : '-';
    bar[40] = '\0';
    std::fprintf(stderr, "\r  [%s] %3d%%  %-12s", bar, pct, stage_.c_str());
    std::fflush(stderr);
  }
  void done() const {
    if (pct_ >= 0) std::fprintf(stderr, "\n");
  }

 private:
  int pct_ = -1;
  std::string stage_;
};

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path model_path, out_path;
  assets::SphereFitOptions options;
  bool have_n = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "-n") {
      const char* v = value();
      if (v == nullptr || !parse_number(v, options.count))
        return usage("-n needs an integer sphere count");
      have_n = true;
    } else if (a == "-o") {
      const char* v = value();
      if (v == nullptr) return usage("-o needs a file name");
      out_path = v;
    } else if (a == "--method") {
      const char* v = value();
      if (v != nullptr && std::strcmp(v, "kmeans") == 0) {
        options.method = assets::SphereFitMethod::kKMeans;
      } else if (v != nullptr && std::strcmp(v, "variational") == 0) {
        options.method = assets::SphereFitMethod::kVariational;
      } else {
        return usage("--method is kmeans or variational");
      }
    } else if (a == "--seed") {
      const char* v = value();
      if (v == nullptr || !parse_number(v, options.seed)) return usage("--seed needs an integer");
    } else if (a == "--surface-samples" || a == "--volume-cells" || a == "--iterations") {
      int& target = a == "--surface-samples" ? options.surface_samples
                    : a == "--volume-cells"  ? options.volume_cells
                                             : options.max_iterations;
      const char* v = value();
      if (v == nullptr || !parse_number(v, target))
        return usage(std::string(a) + " needs an integer");
    } else if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + std::string(a));
    } else if (model_path.empty()) {
      model_path = a;
    } else {
      return usage("more than one model");
    }
  }
  if (model_path.empty()) return usage("no model");
  if (!have_n) return usage("no sphere count (-n N)");
  if (out_path.empty()) return usage("no output file (-o FILE)");

  ProgressBar bar;
  options.progress = [&bar](double f, std::string_view stage) { bar(f, stage); };
  try {
    const assets::Model model = assets::load_gltf(model_path);
    const data::MeshData mesh = assets::merge_instances(model);
    const assets::SphereFitResult fit = assets::fit_spheres(mesh, options);
    bar.done();
    assets::write_sphere_file(out_path,
                              assets::to_sphere_file(fit, model_path.filename().string()));
    float rmin = fit.spheres.front().radius, rmax = rmin;
    for (const data::Sphere& s : fit.spheres) {
      rmin = std::min(rmin, s.radius);
      rmax = std::max(rmax, s.radius);
    }
    const assets::SphereSetError& e = fit.error;
    std::printf("sphere set  %s -> %s\n", model_path.c_str(), out_path.c_str());
    std::printf(
        "  method      %s (%d %s)\n", assets::sphere_fit_method_name(fit.method), fit.iterations,
        fit.method == assets::SphereFitMethod::kVariational ? "iterations after the k-means start"
                                                            : "Lloyd iterations");
    std::printf("  spheres     %zu, radius %.4g .. %.4g\n", fit.spheres.size(), rmin, rmax);
    std::printf(
        "  Er          %.4f  vol(union)/vol(mesh) - 1 (%zu Monte Carlo points: mesh %.4g, "
        "union %.4g)\n",
        e.outside_volume_ratio, e.eval_samples, e.mesh_volume, e.union_volume);
    std::printf("  coverage    %.6f of %zu fresh surface samples (volume %.6f)\n", e.coverage,
                e.coverage_samples, e.volume_coverage);
    std::printf("  T (eq. 1)   %.4g  sum of per-sphere outside volumes\n", fit.outside_volume_sum);
    std::printf("  samples     %zu surface + %zu inside\n", fit.surface_points, fit.volume_points);
    std::printf("  time        %.2f s\n", fit.seconds);
  } catch (const std::exception& ex) {
    bar.done();
    std::fprintf(stderr, "%s\n", ex.what());
    return 1;
  }
  return 0;
}
