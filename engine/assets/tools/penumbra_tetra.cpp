// penumbra_tetra POINTS -o FILE.pcld [--bands N] [--merge-distance M] (./penumbra tetra):
// tetrahedralizes a probe point file (probe_points.h: x y z per line, optionally 3 N^2 SH
// values after them) into a probe cloud file (probe_cloud_file.h) with
// probe_cloud::build_probe_cloud, runs probe_cloud::validate_probe_cloud on the result and
// writes it atomically; prints the counts (points, merged duplicates, coordinates snapped onto
// the bounding box's faces, probes, tetrahedra, hull faces = outer cells) and the times. Exit 1 on
// a load, build, validation or write error (the message names the file and the reason; nothing is
// written), 2 on bad arguments. Built by systems/CMakeLists.txt, since it links the probe-cloud
// system.
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/assets/probe_points.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

namespace {

using namespace penumbra;
using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: penumbra_tetra POINTS -o FILE.pcld [--bands N] [--merge-distance M]\n"
    "  POINTS: text, one probe per line: x y z [3 N^2 SH values]; '#' comments\n"
    "  --bands N           SH bands of the probes, 2..4 (default 3)\n"
    "  --merge-distance M  probes closer than M metres are merged (default 0.001; 0: exact "
    "duplicates only)\n";

int usage(const std::string& why) {
  std::fprintf(stderr, "penumbra_tetra: %s\n%s", why.c_str(), kUsage);
  return 2;
}

template <class T>
bool parse_number(std::string_view s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path points_path, out_path;
  probe_cloud::ProbeCloudBuildSettings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "-o") {
      const char* v = value();
      if (v == nullptr) return usage("-o needs a file name");
      out_path = v;
    } else if (a == "--bands") {
      const char* v = value();
      if (v == nullptr || !parse_number(v, settings.bands) ||
          settings.bands < data::kProbeMinBands || settings.bands > data::kProbeMaxBands)
        return usage("--bands needs an integer in 2..4");
    } else if (a == "--merge-distance") {
      const char* v = value();
      if (v == nullptr || !parse_number(v, settings.merge_distance) ||
          !std::isfinite(settings.merge_distance) || settings.merge_distance < 0)
        return usage("--merge-distance needs a finite number >= 0 (metres)");
    } else if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + std::string(a));
    } else if (points_path.empty()) {
      points_path = a;
    } else {
      return usage("more than one points file");
    }
  }
  if (points_path.empty()) return usage("no points file");
  if (out_path.empty()) return usage("no output file (-o FILE.pcld)");

  try {
    auto t0 = Clock::now();
    const assets::ProbePoints points = assets::load_probe_points(points_path, settings.bands);
    const double read_ms = ms_since(t0);
    probe_cloud::ProbeCloudBuildReport report;
    data::ProbeCloud cloud;
    try {
      cloud = probe_cloud::build_probe_cloud(points.positions, points.sh, settings, &report);
    } catch (const std::invalid_argument& e) {  // names the point index, not the file
      std::fprintf(stderr, "%s: %s\n", points_path.c_str(), e.what());
      return 1;
    }
    t0 = Clock::now();
    const probe_cloud::ProbeCloudValidation validation = probe_cloud::validate_probe_cloud(cloud);
    const double validate_ms = ms_since(t0);
    if (!validation.ok()) {
      std::fprintf(stderr,
                   "%s: the tetrahedralization failed validation (%zu errors), %s not "
                   "written:\n",
                   points_path.c_str(), validation.errors.size(), out_path.c_str());
      for (const std::string& e : validation.errors) std::fprintf(stderr, "  %s\n", e.c_str());
      return 1;
    }
    t0 = Clock::now();
    assets::save_probe_cloud_file(out_path, cloud);
    const double write_ms = ms_since(t0);
    const std::size_t n = cloud.probe_count();
    std::printf("probe cloud  %s -> %s\n", points_path.c_str(), out_path.c_str());
    std::printf("  points             %zu (%s)\n", report.input_points,
                points.sh.empty() ? "no SH: zeros" : "with SH");
    std::printf("  merged duplicates  %zu (closer than %g m)\n", report.merged_duplicates,
                static_cast<double>(settings.merge_distance));
    std::printf("  snapped to faces   %zu coordinates (within %g of the box's shortest side)\n",
                report.snapped_coordinates, static_cast<double>(settings.face_snap));
    std::printf("  probes             %zu, %d bands\n", n, cloud.bands);
    std::printf("  tetrahedra         %zu", report.tetrahedra);
    if (n > 0) std::printf(" (%.3f per probe)", static_cast<double>(report.tetrahedra) / n);
    std::printf("\n  hull faces         %zu (outer cells)\n", report.outer_cells);
    if (cloud.cells.empty() && n > 0)
      std::printf("  (no cells: fewer than 4 probes or all coplanar)\n");
    std::printf("  validation         OK\n");
    std::printf(
        "  time               %.2f ms tetrahedralization (read %.2f, validate %.2f, "
        "write %.2f ms)\n",
        report.seconds * 1e3, read_ms, validate_ms, write_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
