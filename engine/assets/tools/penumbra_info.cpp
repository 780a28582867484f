// penumbra_info FILE: what an asset file holds (./penumbra info FILE). Environment map (.exr
// with colour channels): size, radiance range and mean, 4-band SH per channel, and the light
// sources detected in it (systems/environment, default settings: direction as a unit vector and
// azimuth/elevation, angular radius, share of the map's energy). glTF (.gltf,
// .glb): meshes, vertices, triangles, nodes. Height map (.pgm, single-channel .exr): size, cell
// size, height range. Sphere set (.psph): count, roots, radius range, bounds of the set, fit
// method, Er, coverage, source model. Probe cloud (.pcld): probes, bands, inner tetrahedra,
// outer cells, bounds, tetrahedra per probe, and the validation pass
// (probe_cloud::validate_probe_cloud): OK or its errors. On a load error prints the loader's
// message and exits 1; on a failed validation prints the errors and exits 1.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/assets/sphere_file.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/environment/light_source_detection.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

namespace {

using namespace penumbra;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void print_environment(const data::EnvironmentMap& m, double ms) {
  std::printf("environment map  %s\n  size        %d x %d texels, linear RGB\n", m.source.c_str(),
              m.width, m.height);
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  double mean[3] = {0, 0, 0};
  for (int y = 0; y < m.height; ++y) {
    const double w = sh::equirect_texel_solid_angle(y, m.width, m.height) / (4 * 3.14159265358979);
    for (int x = 0; x < m.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = m.texel(x, y)[c];
        lo[c] = std::min(lo[c], v);
        hi[c] = std::max(hi[c], v);
        mean[c] += w * v;
      }
  }
  const char* names = "RGB";
  for (int c = 0; c < 3; ++c)
    std::printf("  radiance %c  min %.5g  max %.5g  mean %.5g (solid-angle weighted)\n", names[c],
                lo[c], hi[c], mean[c]);
  std::printf("  clamped     %zu negative values (compression ringing, exr.h)\n", m.clamped_values);
  const auto coeffs = sh::project_equirect<4>(m.rgb.data(), m.width, m.height);
  std::printf("  SH, 4 bands (index l(l+1)+m, penumbra/sh conventions)\n");
  for (int c = 0; c < 3; ++c) {
    std::printf("    %c", names[c]);
    for (float v : coeffs[static_cast<std::size_t>(c)]) std::printf(" %.5g", v);
    std::printf("\n");
  }
  std::printf("  loaded in  %.2f ms\n", ms);
  const environment::DetectionSettings settings;
  const environment::LightSourceDetection d = environment::detect_light_sources(m, settings);
  std::printf("  sources     %zu of %d requested (percentiles %.0f/%.0f, %.2f ms)%s%s\n",
              d.sources.size(), settings.source_count,
              static_cast<double>(settings.light_percentile),
              static_cast<double>(settings.halo_percentile), d.milliseconds,
              d.stop.empty() ? "" : "; stopped: ", d.stop.c_str());
  for (std::size_t i = 0; i < d.sources.size(); ++i) {
    const environment::DetectedSource& s = d.sources[i];
    std::printf(
        "    %zu  direction (%.4f, %.4f, %.4f)  azimuth %.2f deg  elevation %.2f deg  radius %.2f "
        "deg  energy %.2f%%\n",
        i, static_cast<double>(s.direction.x), static_cast<double>(s.direction.y),
        static_cast<double>(s.direction.z), static_cast<double>(s.azimuth_deg),
        static_cast<double>(s.elevation_deg),
        static_cast<double>(s.angular_radius) * 180.0 / 3.14159265358979,
        100.0 * static_cast<double>(s.energy_share));
  }
}

void print_model(const assets::Model& m, double ms) {
  std::printf("glTF model  %s\n", m.source.c_str());
  std::printf("  meshes      %zu (%zu triangle primitives)\n", m.gltf_mesh_count, m.meshes.size());
  std::printf("  vertices    %zu\n  triangles   %zu\n", m.vertex_count(), m.triangle_count());
  std::printf("  nodes       %zu (%zu mesh instances in the scene)\n", m.node_count,
              m.instances.size());
  for (const std::string& w : m.warnings) std::printf("  warning     %s\n", w.c_str());
  std::printf("  loaded in   %.2f ms\n", ms);
}

void print_heights(const data::HeightField& f, double ms) {
  const auto [lo, hi] = std::minmax_element(f.heights.begin(), f.heights.end());
  double mean = 0;
  for (float h : f.heights) mean += h;
  mean /= static_cast<double>(f.heights.size());
  std::printf("height map  %s\n  size        %d x %d samples\n", f.source.c_str(), f.width,
              f.height);
  std::printf("  cell size   %.6g m (%.6g x %.6g m)\n", f.cell_size, f.cell_size * (f.width - 1),
              f.cell_size * (f.height - 1));
  std::printf("  heights     min %.6g  max %.6g  mean %.6g m\n", *lo, *hi, mean);
  std::printf("  loaded in   %.2f ms\n", ms);
}

void print_spheres(const assets::SphereSetFile& f, const std::string& path, double ms) {
  std::printf("sphere set  %s\n", path.c_str());
  std::printf("  source      %s\n", f.source_model.empty() ? "(none)" : f.source_model.c_str());
  std::size_t roots = 0;
  float rmin = 0, rmax = 0;
  glm::vec3 lo(0), hi(0);
  for (std::size_t i = 0; i < f.spheres.size(); ++i) {
    const data::Sphere& s = f.spheres[i];
    roots += s.parent < 0;
    rmin = i == 0 ? s.radius : std::min(rmin, s.radius);
    rmax = i == 0 ? s.radius : std::max(rmax, s.radius);
    lo = i == 0 ? s.centre - s.radius : glm::min(lo, s.centre - s.radius);
    hi = i == 0 ? s.centre + s.radius : glm::max(hi, s.centre + s.radius);
  }
  std::printf("  spheres     %zu (%zu roots)\n", f.spheres.size(), roots);
  if (!f.spheres.empty()) {
    std::printf("  radius      min %.6g  max %.6g\n", rmin, rmax);
    std::printf("  bounds      (%.4g, %.4g, %.4g) .. (%.4g, %.4g, %.4g)\n", lo.x, lo.y, lo.z, hi.x,
                hi.y, hi.z);
  }
  std::printf("  method      %s\n", assets::sphere_fit_method_name(f.method));
  std::printf("  Er          %.4f (outside volume ratio: vol(union)/vol(mesh) - 1)\n",
              f.outside_volume_ratio);
  std::printf("  coverage    %.6f (of the mesh surface)\n", f.coverage);
  std::printf("  loaded in   %.2f ms\n", ms);
}

// Returns false when the validation failed (the errors are printed).
bool print_probe_cloud(const data::ProbeCloud& c, const std::string& path, double ms) {
  std::printf("probe cloud  %s\n", path.c_str());
  const std::size_t n = c.probe_count();
  const std::size_t outer = c.cells.size() - c.inner_count;
  std::printf("  probes      %zu\n", n);
  std::printf("  bands       %d (%zu SH coefficients per probe: 3 channels x %d)\n", c.bands,
              c.coeffs_per_probe(), c.bands * c.bands);
  std::printf("  tetrahedra  %u inner", c.inner_count);
  if (n > 0) std::printf(" (%.3f per probe)", static_cast<double>(c.inner_count) / n);
  std::printf("\n  outer cells %zu (hull faces)\n", outer);
  if (n > 0) {
    glm::vec3 lo = c.positions[0], hi = c.positions[0];
    for (const glm::vec3& p : c.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    std::printf("  bounds      (%.4g, %.4g, %.4g) .. (%.4g, %.4g, %.4g) m\n", lo.x, lo.y, lo.z,
                hi.x, hi.y, hi.z);
  }
  if (c.cells.empty())
    std::printf("  (no cells: fewer than 4 probes or all coplanar; lookups fall back)\n");
  std::printf("  loaded in   %.2f ms\n", ms);
  const auto t0 = Clock::now();
  const probe_cloud::ProbeCloudValidation v = probe_cloud::validate_probe_cloud(c);
  if (v.ok()) {
    std::printf("  validation  OK (%.2f ms)\n", ms_since(t0));
    return true;
  }
  std::printf("  validation  FAILED, %zu errors:\n", v.errors.size());
  for (const std::string& e : v.errors) std::printf("    %s\n", e.c_str());
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: penumbra_info FILE (.exr, .gltf, .glb, .pgm, .psph, .pcld)\n");
    return 2;
  }
  const std::filesystem::path path = argv[1];
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  try {
    const auto t0 = Clock::now();
    if (ext == ".gltf" || ext == ".glb") {
      const assets::Model m = assets::load_gltf(path);
      print_model(m, ms_since(t0));
    } else if (ext == ".pgm" || (ext == ".exr" && assets::exr_channel_count(path) == 1)) {
      const data::HeightField f = assets::load_height_field(path);
      print_heights(f, ms_since(t0));
    } else if (ext == ".exr") {
      const data::EnvironmentMap m = assets::load_environment_map(path);
      print_environment(m, ms_since(t0));
    } else if (ext == ".psph") {
      const assets::SphereSetFile f = assets::load_sphere_file(path);
      print_spheres(f, path.string(), ms_since(t0));
    } else if (ext == ".pcld") {
      const data::ProbeCloud c = assets::load_probe_cloud_file(path);
      if (!print_probe_cloud(c, path.string(), ms_since(t0))) return 1;
    } else {
      std::fprintf(stderr,
                   "%s: unknown file type (expected .exr, .gltf, .glb, .pgm, .psph or .pcld)\n",
                   path.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
