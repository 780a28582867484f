// A host engine with its own object storage (plain arrays, as with EnTT or flecs) lighting its
// objects through Penumbra's plain-data APIs, without Penumbra's ECS:
//   terrain:  TerrainShadowing  (height field -> irradiance per texel)
//   blockers: BlockerAccumulation (spheres + receivers -> irradiance, shadowed by the spheres)
//   probes:   build_probe_cloud + ProbeTetWalk (probe cloud + points -> SH)
// Prints a few numbers; exits 1 when a result is not finite or not plausible.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace {

namespace pn = penumbra;

// The host's objects: structure of arrays, its own layout.
struct HostObjects {
  std::vector<glm::vec3> position;
  std::vector<float> radius;
  std::vector<glm::vec3> irradiance;  // filled by the blocker system's receivers below
};

int failures = 0;
void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "host_engine: FAILED: %s\n", what);
    ++failures;
  }
}
bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A uniform sky of radiance L (W/m^2/sr): only the constant SH coefficient, 2 sqrt(pi) L. An
// open, flat receiver gets E = pi L.
template <int N>
pn::sh::CoeffsRgb<N> uniform_sky(float radiance) {
  pn::sh::CoeffsRgb<N> sky{};
  for (auto& channel : sky) channel[0] = 2.0f * std::sqrt(std::numbers::pi_v<float>) * radiance;
  return sky;
}

constexpr float kSky = 1.0f;
constexpr float kOpen = std::numbers::pi_v<float> * kSky;  // E of an open flat receiver

void light_terrain() {
  // 64 x 64 samples, 1 m apart: flat ground with a 12 m hill in the middle.
  auto field = std::make_shared<pn::data::HeightField>();
  field->width = field->height = 64;
  field->source = "host_engine hill";
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float dx = static_cast<float>(x - 32), dy = static_cast<float>(y - 32);
      field->heights.push_back(12.0f * std::exp(-(dx * dx + dy * dy) / 60.0f));
    }
  pn::terrain_shadow::TerrainShadowing<3> terrain;
  terrain.update(field, 1.0f);
  std::vector<glm::vec3> e;
  terrain.shade_environment(uniform_sky<3>(kSky), e);

  float lo = e[0].x, hi = e[0].x;
  bool ok = e.size() == field->heights.size();
  for (const glm::vec3& v : e) {
    ok = ok && finite(v) && v.x >= 0.0f && v.x <= 1.01f * kOpen;
    lo = std::min(lo, v.x);
    hi = std::max(hi, v.x);
  }
  const float foot = e[32 * 64 + 24].x;  // at the hill's foot: the hill hides part of the sky
  std::printf("terrain: %zu texels, E in [%.3f, %.3f], at the hill's foot %.3f (open: %.3f)\n",
              e.size(), lo, hi, foot, kOpen);
  check(ok, "terrain irradiance finite and in [0, pi L]");
  check(hi > 0.95f * kOpen, "open ground sees the whole sky");
  check(foot < 0.95f * hi, "the hill shadows its foot");
}

void light_objects(HostObjects& objects) {
  // The host's objects are the blockers; each object's receiver is a point on the ground below it.
  std::vector<pn::blocker_accumulation::WorldSphere> spheres;
  std::vector<glm::vec3> points, normals;
  for (std::size_t i = 0; i < objects.position.size(); ++i) {
    spheres.push_back({objects.position[i], objects.radius[i]});
    points.push_back({objects.position[i].x, objects.position[i].y, 0.0f});
    normals.push_back({0.0f, 0.0f, 1.0f});
  }
  points.push_back({100.0f, 100.0f, 0.0f});  // and one far from every object
  normals.push_back({0.0f, 0.0f, 1.0f});

  pn::blocker_accumulation::BlockerAccumulation<4> blockers;
  blockers.set_blockers(spheres);
  std::vector<glm::vec3> e(points.size());
  blockers.shade(uniform_sky<4>(kSky), points, normals, {}, e);
  objects.irradiance.assign(e.begin(), e.end() - 1);

  bool ok = true;
  for (const glm::vec3& v : e) ok = ok && finite(v) && v.x >= 0.0f && v.x <= 1.01f * kOpen;
  std::printf("blockers: %zu spheres, E below object 0 %.3f, far from all %.3f\n", spheres.size(),
              e[0].x, e.back().x);
  check(ok, "receiver irradiance finite and in [0, pi L]");
  check(std::abs(e.back().x - kOpen) < 0.02f * kOpen, "a lone receiver sees the open sky");
  check(e[0].x < 0.9f * kOpen, "an object shadows the ground below it");
}

void light_from_probes(const HostObjects& objects) {
  // A 3 x 3 x 3 probe lattice, 10 m apart, whose irradiance grows with height: the constant
  // coefficient is 1 + z / 10 in every channel.
  std::vector<glm::vec3> probes;
  std::vector<float> sh;
  const int coeffs = pn::data::kProbeDefaultBands * pn::data::kProbeDefaultBands;
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        probes.push_back(glm::vec3(x - 1, y - 1, z) * 10.0f);
        for (int c = 0; c < 3; ++c)
          for (int i = 0; i < coeffs; ++i)
            sh.push_back(i == 0 ? 1.0f + static_cast<float>(z) : 0.0f);
      }
  auto cloud =
      std::make_shared<const pn::data::ProbeCloud>(pn::probe_cloud::build_probe_cloud(probes, sh));
  const pn::probe_cloud::ProbeTetWalk walk(cloud);

  // The host keeps each object's last cell (here all start unknown: -1).
  std::vector<std::int32_t> cells(objects.position.size(), pn::probe_cloud::kNoCell);
  std::vector<pn::probe_cloud::ProbeSh> out(objects.position.size());
  walk.locate_batch(objects.position, cells, out);

  bool ok = cloud->inner_count > 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float expected = 1.0f + objects.position[i].z / 10.0f;  // linear: exact in a tetrahedron
    ok = ok && cells[i] >= 0 && std::isfinite(out[i][0][0]) &&
         std::abs(out[i][0][0] - expected) < 1e-3f;
  }
  std::printf("probes: %zu probes, %u tetrahedra, object 0 in cell %d, SH[0] %.3f\n",
              cloud->probe_count(), cloud->inner_count, cells[0], out[0][0][0]);
  check(ok, "probe SH interpolated linearly inside the cloud");
}

}  // namespace

int main() {
  HostObjects objects;
  for (int i = 0; i < 4; ++i) {
    objects.position.push_back(
        {-6.0f + 4.0f * static_cast<float>(i), 1.5f, 2.0f + 1.5f * static_cast<float>(i)});
    objects.radius.push_back(1.0f);
  }
  try {
    light_terrain();
    light_objects(objects);
    light_from_probes(objects);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "host_engine: %s\n", e.what());
    return 1;
  }
  if (failures > 0) {
    std::fprintf(stderr, "host_engine: %d check(s) failed\n", failures);
    return 1;
  }
  std::printf("host_engine: OK\n");
  return 0;
}
