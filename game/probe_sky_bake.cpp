#include "penumbra/game/probe_sky_bake.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <system_error>

#include "penumbra/assets/checksum.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/reference/radiance_sh.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/convolution.h"

namespace penumbra::game {
namespace {

constexpr int kBakeBands = 3;  // the cloud's ([Cupisz12]; data::kProbeDefaultBands)
constexpr int kCoeffs = kBakeBands * kBakeBands;

// FNV-1a 64 over a sequence of byte ranges (assets/checksum.h's constants).
struct Hasher {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
};

void check(const ProbeSkyBakeInputs& in) {
  if (!in.field || !in.map || in.map->width < 1 || in.map->height < 1)
    throw std::invalid_argument("probe sky bake: needs a height field and an environment map");
  if (in.steps < 1 || in.samples < 2)
    throw std::invalid_argument("probe sky bake: steps >= 1 and samples >= 2 needed");
}

// One step's SH: the capture under the map turned by 2 pi k / steps, convolved to irradiance.
std::vector<float> bake_step(const ProbeSkyBakeInputs& in, std::span<const glm::vec3> positions,
                             int k) {
  reference::SceneDesc desc;
  desc.height_fields.push_back({*in.field, in.origin, in.albedo});
  for (const BakeMesh& m : in.meshes)
    if (m.mesh) desc.meshes.push_back({*m.mesh, glm::mat4(1.0f), m.albedo});
  desc.environment =
      reference::EnvironmentLight{*in.map, 2 * std::numbers::pi_v<float> * static_cast<float>(k) /
                                               static_cast<float>(in.steps)};
  const reference::Scene scene(desc);
  reference::RadianceShOptions o;
  o.samples = in.samples;
  o.bounce = in.bounce;
  o.seed = in.seed;  // the same streams at every step: the noise moves with the sky, not per step
  const auto est = reference::radiance_sh<kBakeBands>(scene, positions, o);
  std::vector<float> out(positions.size() * 3 * kCoeffs);
  for (std::size_t p = 0; p < est.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const sh::Coeffs<kBakeBands> e = sh::irradiance_convolve<kBakeBands>(est[p].mean[c]);
      std::memcpy(&out[(p * 3 + static_cast<std::size_t>(c)) * kCoeffs], e.data(),
                  sizeof(float) * kCoeffs);
    }
  return out;
}

std::filesystem::path step_file(const std::filesystem::path& folder, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "sky_%03d.pcld", k);
  return folder / name;
}

}  // namespace

std::uint64_t probe_sky_bake_key(const ProbeSkyBakeInputs& in,
                                 std::span<const glm::vec3> positions) {
  check(in);
  Hasher h;
  h.value(kProbeSkyBakeVersion);
  h.value(in.field->width);
  h.value(in.field->height);
  h.value(in.field->cell_size);
  h.bytes(in.field->heights.data(), in.field->heights.size() * sizeof(float));
  h.value(in.origin);
  h.value(in.albedo);
  h.value(in.map->width);
  h.value(in.map->height);
  h.bytes(in.map->rgb.data(), in.map->rgb.size() * sizeof(float));
  h.bytes(positions.data(), positions.size() * sizeof(glm::vec3));
  h.value(in.steps);
  h.value(in.samples);
  h.value(in.bounce);
  h.value(in.seed);
  for (const BakeMesh& m : in.meshes) {
    if (!m.mesh) continue;
    h.bytes(m.mesh->positions.data(), m.mesh->positions.size() * sizeof(glm::vec3));
    h.bytes(m.mesh->indices.data(), m.mesh->indices.size() * sizeof(std::uint32_t));
    h.value(m.albedo);
  }
  return h.h;
}

ProbeSkySteps bake_probe_sky_steps(const ProbeSkyBakeInputs& in, const data::ProbeCloud& cloud,
                                   const std::filesystem::path& cache_dir,
                                   std::span<const int> which) {
  check(in);
  if (cloud.bands != kBakeBands)
    throw std::invalid_argument("probe sky bake: the cloud must have 3 bands");
  const auto t0 = std::chrono::steady_clock::now();
  ProbeSkySteps out;
  out.sh.resize(static_cast<std::size_t>(in.steps));
  std::vector<int> steps(which.begin(), which.end());
  if (steps.empty())
    for (int k = 0; k < in.steps; ++k) steps.push_back(k);
  for (int k : steps)
    if (k < 0 || k >= in.steps)
      throw std::invalid_argument("probe sky bake: step " + std::to_string(k) + " out of range");
  if (!cache_dir.empty()) {
    char key[32];
    std::snprintf(key, sizeof key, "probe_sky_%016llx",
                  static_cast<unsigned long long>(probe_sky_bake_key(in, cloud.positions)));
    out.folder = cache_dir / key;
  }
  bool writable = !out.folder.empty();
  for (int k : steps) {
    std::vector<float>& sh = out.sh[static_cast<std::size_t>(k)];
    const std::filesystem::path file = out.folder.empty() ? "" : step_file(out.folder, k);
    if (!file.empty() && std::filesystem::exists(file)) {
      try {
        data::ProbeCloud c = assets::load_probe_cloud_file(file);
        if (c.bands == kBakeBands && c.positions == cloud.positions) {
          sh = std::move(c.sh);
          ++out.loaded;
          continue;
        }
        out.notes.push_back(file.string() + ": holds other probes; baked again");
      } catch (const std::exception& e) {
        out.notes.push_back(std::string(e.what()) + "; baked again");
      }
    }
    sh = bake_step(in, cloud.positions, k);
    ++out.baked;
    if (!writable) continue;
    try {
      std::filesystem::create_directories(out.folder);
      data::ProbeCloud c = cloud;
      c.sh = sh;
      assets::save_probe_cloud_file(file, c);
    } catch (const std::exception& e) {
      out.notes.push_back(std::string("cache not written: ") + e.what());
      writable = false;  // one note, no retries
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace penumbra::game
