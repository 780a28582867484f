// Accuracy of the blocker accumulation on fitted meshes and on many blockers over the elevation
// model, against the reference integrator (engine/reference). Irradiance at upward receivers on
// the ground (or the terrain), relative to the mean open-sky reference irradiance, against
// (i) the reference with the exact visibility of the fitted spheres and (ii) that of the original
// mesh, so the SH / exponential error and the sphere-fit error show apart. Sources: [Giraud]
// sec. 4.2 (log-SH sums, eps, ratio attenuation), [Guerrero08] sec. 4.1 (the variational fit),
// [Ren06] (OL / HYB exponentials, the product of visibilities, the hierarchy). Measured values
// are printed; the bounds sit above them with margin for the reference's noise. The table is in
// docs/blocker_accuracy.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/sphere_fit.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/blocker_accumulation/terrain_receivers.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

const std::filesystem::path kData = PENUMBRA_SHARED_DATA;
constexpr int kSamples = 2048;  // reference directions per receiver

using test::uniform_sky;

// The HDR map: sky.exr (a clear sky with its sun), or the file of ../shared/data/hdri that
// PENUMBRA_ACCURACY_SKY names (forest.exr, dawn.exr: docs/blocker_accuracy.md).
const char* hdr_name() {
  const char* name = std::getenv("PENUMBRA_ACCURACY_SKY");
  return name && *name ? name : "sky.exr";
}

data::EnvironmentMap sky_map() {
  return assets::load_environment_map(kData / "hdri" / hdr_name());
}

struct Errors {
  float rms = 0, max = 0;  // relative to the mean open-sky reference irradiance
};

// `ours` against `ref`, relative to `open_mean`.
Errors compare(const std::vector<float>& ours, const std::vector<float>& ref, double open_mean) {
  Errors e;
  double sq = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_TRUE(std::isfinite(ours[i])) << i;
    const double d = (ours[i] - ref[i]) / open_mean;
    sq += d * d;
    e.max = std::max(e.max, static_cast<float>(std::abs(d)));
  }
  e.rms = static_cast<float>(std::sqrt(sq / ours.size()));
  return e;
}

std::vector<float> reference_irradiance(const reference::SceneDesc& desc,
                                        const std::vector<reference::Receiver>& receivers,
                                        int samples = kSamples) {
  const reference::Scene scene(desc);
  reference::IrradianceOptions o;
  o.samples = samples;
  std::vector<float> out;
  for (const auto& r : reference::environment_irradiance(scene, receivers, o))
    out.push_back(r.mean.y);
  return out;
}

double mean(const std::vector<float>& v) {
  double m = 0;
  for (const float x : v) m += x / v.size();
  return m;
}

void print_row(const std::string& scene, const std::string& method, const Errors& vs_spheres,
               const Errors& vs_mesh) {
  std::printf("| %s | %s | %.2f%% | %.2f%% | %.2f%% | %.2f%% |\n", scene.c_str(), method.c_str(),
              100 * vs_spheres.rms, 100 * vs_spheres.max, 100 * vs_mesh.rms, 100 * vs_mesh.max);
}

// ---------------------------------------------------------------------------------------------
// A model over a ground plane: the mesh scaled to a bounding-box half-diagonal of 1, centred on
// the z axis, its lowest point 0.5 above the ground (z = 0). Upward receivers on the ground on
// an 11 x 11 grid over [-3, 3]^2 (the plane itself is below every receiver's horizon, so it is
// left out of the reference scene).

struct ModelScene {
  std::string name;
  data::MeshData mesh;  // world frame
  std::vector<reference::Receiver> receivers;
};

ModelScene load_model(const std::string& file) {
  ModelScene s;
  s.name = file.substr(0, file.find('.'));
  s.mesh = assets::merge_instances(assets::load_gltf(kData / "models" / file));
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : s.mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float scale = 2 / glm::length(hi - lo);
  const glm::vec3 centre = 0.5f * (lo + hi);
  for (glm::vec3& p : s.mesh.positions) {
    p = scale * (p - centre);
    p.z += scale * 0.5f * (hi.z - lo.z) + 0.5f;
  }
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i)
      s.receivers.push_back({{-3.0f + 0.6f * i, -3.0f + 0.6f * j, 0.0f}, {0, 0, 1}});
  return s;
}

std::vector<WorldSphere> fit(const data::MeshData& mesh, int count) {
  assets::SphereFitOptions o;
  o.count = count;
  o.method = assets::SphereFitMethod::kVariational;
  o.seed = 1;
  o.eval_samples = 1 << 14;  // the figures are not used here
  o.coverage_samples = 1 << 12;
  std::vector<WorldSphere> out;
  for (const data::Sphere& s : assets::fit_spheres(mesh, o).spheres)
    out.push_back({s.centre, s.radius});
  return out;
}

// The references of one model under one sky: open, mesh, and each sphere set.
struct References {
  std::vector<float> open, mesh;
  double open_mean = 0;
};

References model_references(const ModelScene& m, const data::EnvironmentMap& sky) {
  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{sky, 0.0f};
  References r;
  r.open = reference_irradiance(desc, m.receivers);
  r.open_mean = mean(r.open);
  desc.meshes.push_back({m.mesh, glm::mat4(1.0f)});
  r.mesh = reference_irradiance(desc, m.receivers);
  return r;
}

std::vector<float> sphere_reference(const std::vector<WorldSphere>& spheres,
                                    const data::EnvironmentMap& sky,
                                    const std::vector<reference::Receiver>& receivers) {
  reference::SceneDesc desc;
  desc.environment = reference::EnvironmentLight{sky, 0.0f};
  for (const WorldSphere& s : spheres) desc.spheres.push_back({s.centre, s.radius, ""});
  return reference_irradiance(desc, receivers);
}

// The library's irradiance, the spheres as one object (one group: its bound and coverage).
template <int B>
std::vector<float> ours(const std::vector<WorldSphere>& spheres, const data::EnvironmentMap& sky,
                        const std::vector<reference::Receiver>& receivers,
                        const BlockerSettings& settings = {}) {
  BlockerAccumulation<B> acc(settings);
  acc.set_blockers(spheres, {bound_group(spheres)});
  const sh::CoeffsRgb<B> radiance = sh::project_equirect<B>(sky.rgb.data(), sky.width, sky.height);
  std::vector<float> out;
  for (const reference::Receiver& r : receivers)
    out.push_back(acc.irradiance(radiance, r.position, r.normal).y);
  return out;
}

// Product shading with another exponential of the library's log-visibility sum.
using ExpFn = std::function<sh::Coeffs<4>(const sh::Coeffs<4>&)>;
std::vector<float> ours_with_exp(const std::vector<WorldSphere>& spheres,
                                 const data::EnvironmentMap& sky,
                                 const std::vector<reference::Receiver>& receivers,
                                 const ExpFn& exp) {
  BlockerAccumulation<4> acc;
  acc.set_blockers(spheres, {bound_group(spheres)});
  const sh::CoeffsRgb<4> radiance = sh::project_equirect<4>(sky.rgb.data(), sky.width, sky.height);
  std::vector<float> out;
  for (const reference::Receiver& r : receivers) {
    const sh::Coeffs<4> v = exp(acc.log_visibility(r.position, r.normal));
    const sh::Coeffs<4> t =
        sh::product<4>(v, sh::rotate_zh<4>(sh::zh_clamped_cosine<4>(), r.normal));
    out.push_back(sh::dot<4>(radiance[1], t));
  }
  return out;
}

// No logarithm: the SH product of every sphere's own visibility 1 - w cap
// (w the plane rule's weight), each product truncated to 4 bands; every sphere at every receiver.
std::vector<float> ours_product_of_visibilities(const std::vector<WorldSphere>& spheres,
                                                const data::EnvironmentMap& sky,
                                                const std::vector<reference::Receiver>& receivers) {
  const sh::CoeffsRgb<4> radiance = sh::project_equirect<4>(sky.rgb.data(), sky.width, sky.height);
  const SphereBlockerSettings settings;
  std::vector<float> out;
  for (const reference::Receiver& r : receivers) {
    sh::Coeffs<4> v{};
    v[0] = std::sqrt(4 * std::numbers::pi_v<float>);  // the constant 1
    for (const WorldSphere& s : spheres) {
      const BlockerView view = view_blocker(r.position, r.normal, s.centre, s.radius, settings);
      if (!(view.weight > 0)) continue;
      const sh::Coeffs<4> cap =
          sh::rotate_zh<4>(sh::zh_cap<4>(std::asin(view.sin_angle)), view.axis);
      sh::Coeffs<4> vi{};
      vi[0] = std::sqrt(4 * std::numbers::pi_v<float>);
      for (int k = 0; k < 16; ++k) vi[k] -= view.weight * cap[k];
      v = sh::product<4>(v, vi);
    }
    const sh::Coeffs<4> t =
        sh::product<4>(v, sh::rotate_zh<4>(sh::zh_clamped_cosine<4>(), r.normal));
    out.push_back(sh::dot<4>(radiance[1], t));
  }
  return out;
}

struct Sky {
  const char* name;
  data::EnvironmentMap map;
};

// Task 1: bunny and Suzanne, 8 / 16 / 32 / 64 spheres (variational, seed 1), uniform sky and
// sky.exr, default settings (4 bands, eps 0.2, product shading, HYB, the object hierarchy).
TEST(BlockerMeshAccuracy, FittedModelsOverAPlane) {
  const Sky skies[] = {{"uniform", uniform_sky()}, {hdr_name(), sky_map()}};
  std::printf(
      "| scene | method | vs spheres RMS | max | vs mesh RMS | max | spheres' ref vs mesh's"
      " ref RMS | max | unclamped HYB vs spheres RMS | max |\n");
  for (const char* file : {"bunny.glb", "suzi.glb"}) {
    const ModelScene m = load_model(file);
    for (const int count : {8, 16, 32, 64}) {
      const std::vector<WorldSphere> spheres = fit(m.mesh, count);
      float lowest = std::numeric_limits<float>::max();
      for (const WorldSphere& s : spheres) lowest = std::min(lowest, s.centre.z - s.radius);
      ASSERT_GT(lowest, 0.0f) << "a sphere reaches the ground";
      for (const Sky& sky : skies) {
        const References ref = model_references(m, sky.map);
        const std::vector<float> ref_spheres = sphere_reference(spheres, sky.map, m.receivers);
        const std::vector<float> e = ours<4>(spheres, sky.map, m.receivers);
        const Errors a = compare(e, ref_spheres, ref.open_mean);
        const Errors b = compare(e, ref.mesh, ref.open_mean);
        const Errors fit_only = compare(ref_spheres, ref.mesh, ref.open_mean);
        // The same sums through the unclamped HYB: what exp_visibility's clamp costs.
        const Errors raw =
            compare(ours_with_exp(spheres, sky.map, m.receivers,
                                  [](const sh::Coeffs<4>& f) { return sh::exp_hyb<4>(f); }),
                    ref_spheres, ref.open_mean);
        std::printf(
            "| %s %d, %s | default | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f%% "
            "| "
            "%.2f%% |\n",
            m.name.c_str(), count, sky.name, 100 * a.rms, 100 * a.max, 100 * b.rms, 100 * b.max,
            100 * fit_only.rms, 100 * fit_only.max, 100 * raw.rms, 100 * raw.max);
        const bool uniform = sky.name[0] == 'u';
        // Measured: uniform 2.1-4.9% against the spheres, 2.5-4.3% against the mesh; sky.exr
        // 10-14% for both (its sun's hard shadow, beyond 4 bands).
        EXPECT_LT(a.rms, uniform ? 0.07f : 0.20f) << m.name << " " << count << " " << sky.name;
        EXPECT_LT(b.rms, uniform ? 0.07f : 0.20f) << m.name << " " << count << " " << sky.name;
        if (uniform) {
          EXPECT_LT(b.max, 0.25f);    // 18.2%
          EXPECT_LT(raw.rms, 0.06f);  // 1.8-3.8%
          EXPECT_LT(raw.max, 0.15f);  // 5.2-9.9%: under the model the clamp costs the most
        }
      }
    }
  }
}

// Task 2: the methods at one scene, the bunny with 32 spheres.
TEST(BlockerMeshAccuracy, MethodsOnTheBunnyWith32Spheres) {
  const ModelScene m = load_model("bunny.glb");
  const std::vector<WorldSphere> spheres = fit(m.mesh, 32);
  const Sky skies[] = {{"uniform", uniform_sky()}, {hdr_name(), sky_map()}};
  for (const Sky& sky : skies) {
    const References ref = model_references(m, sky.map);
    const std::vector<float> ref_spheres = sphere_reference(spheres, sky.map, m.receivers);
    const std::string scene = std::string("bunny 32, ") + sky.name;
    const auto row = [&](const std::string& method, const std::vector<float>& e) {
      const Errors a = compare(e, ref_spheres, ref.open_mean);
      print_row(scene, method, a, compare(e, ref.mesh, ref.open_mean));
      return a;
    };
    const Errors hyb =
        row("HYB, clamped (exp_visibility; default)", ours<4>(spheres, sky.map, m.receivers));
    // The test-side product shading reproduces the library's with its own exponential.
    const std::vector<float> same =
        ours_with_exp(spheres, sky.map, m.receivers,
                      [](const sh::Coeffs<4>& f) { return sh::exp_visibility<4>(f); });
    const std::vector<float> lib = ours<4>(spheres, sky.map, m.receivers);
    for (std::size_t i = 0; i < same.size(); ++i) EXPECT_NEAR(same[i], lib[i], 1e-4f * lib[i]);
    const Errors hyb_raw =
        row("HYB, unclamped (exp_hyb)",
            ours_with_exp(spheres, sky.map, m.receivers,
                          [](const sh::Coeffs<4>& f) { return sh::exp_hyb<4>(f); }));
    const Errors ol =
        row("OL (exp_ol)", ours_with_exp(spheres, sky.map, m.receivers,
                                         [](const sh::Coeffs<4>& f) { return sh::exp_ol<4>(f); }));
    const Errors prod = row("product of per-sphere SH visibilities (no log)",
                            ours_product_of_visibilities(spheres, sky.map, m.receivers));
    BlockerSettings s;
    s.blocker.ratio = RatioAttenuation::kOn;
    const Errors ratio = row("ratio attenuation on", ours<4>(spheres, sky.map, m.receivers, s));
    s = {};
    s.shading = BlockerShading::kLogBrdf;
    const Errors log_brdf =
        row("log-BRDF (eps_brdf 0.01)", ours<4>(spheres, sky.map, m.receivers, s));
    s = {};
    s.blocker.log = BlockerLog::kClippedEigen;
    const Errors eigen =
        row("clipped-eigen log (kClippedEigen)", ours<4>(spheres, sky.map, m.receivers, s));
    std::vector<Errors> eps;
    for (const float e : {0.05f, 0.1f, 0.3f, 0.5f}) {
      s = {};
      s.blocker.epsilon = e;
      char what[32];
      std::snprintf(what, sizeof what, "eps %.2f", e);
      eps.push_back(row(what, ours<4>(spheres, sky.map, m.receivers, s)));
    }
    const Errors b3 = row("3 bands", ours<3>(spheres, sky.map, m.receivers));
    const Errors b5 = row("5 bands", ours<5>(spheres, sky.map, m.receivers));
    s = {};
    s.hierarchy = BlockerHierarchy::kOff;
    const Errors off = row("hierarchy kOff", ours<4>(spheres, sky.map, m.receivers, s));

    if (sky.name[0] == 'u') {
      // Measured (against the spheres): 4.8 / 2.1 / 5.2 / 3.2 / 1.2 / 2.7%; eps 6.5 / 6.3 /
      // 2.2 / 1.7%; 3 / 5 bands 5.6 / 3.8%; kOff 5.0%.
      EXPECT_LT(hyb.rms, 0.07f);
      EXPECT_LT(hyb_raw.rms, 0.04f);
      // Under the bunny the HYB DC overshoots (near sqrt(4 pi): "no occlusion"), and
      // exp_visibility's clamp then removes the shadow; the unclamped HYB keeps it.
      EXPECT_LT(hyb_raw.rms, hyb.rms);
      EXPECT_LT(ol.rms, 0.08f);
      EXPECT_LT(prod.rms, 0.05f);
      EXPECT_LT(ratio.rms, 0.03f);
      EXPECT_LT(log_brdf.rms, 0.05f);
      EXPECT_LT(eigen.rms, 0.05f);  // 2.8%
      for (const Errors& e : eps) EXPECT_LT(e.rms, 0.10f);
      EXPECT_LT(b3.rms, 0.08f);
      EXPECT_LT(b5.rms, 0.06f);
      EXPECT_LT(off.rms, 0.07f);
    } else {
      // Measured 8.6-16% (OL 22%): the sun's hard shadow is beyond every variant.
      for (const Errors& e : {hyb, hyb_raw, prod, ratio, log_brdf, eigen, b3, b5, off})
        EXPECT_LT(e.rms, 0.20f);
      EXPECT_LT(ol.rms, 0.30f);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Task 3: 400 spheres over the elevation model (a 97 x 97 crop of the DEM, 74 m cells), the
// terrain's texels as receivers through the system's own terrain path (update_terrain_ratios:
// E(terrain wedges + blockers) / E(terrain wedges)). The terrain's own shadow comes from the
// terrain system, not from here, so ours is that ratio times the reference's terrain-only
// irradiance; the reference with terrain and spheres is the truth. What is measured is then the
// blockers' contribution alone (with the terrain's occlusion shared between them).

std::uint64_t splitmix(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
float uniform01(std::uint64_t& s) {
  return static_cast<float>(splitmix(s) >> 40) / static_cast<float>(1 << 24);
}

TEST(BlockerMeshAccuracy, FourHundredBlockersOverTheElevationModel) {
  const data::HeightField dem =
      assets::load_height_field(kData / "terrain" / "jacksboro_fault_dem.pgm");
  constexpr int kSize = 97;
  const data::HeightField field =
      data::crop(dem, (dem.width - kSize) / 2, (dem.height - kSize) / 2, kSize, kSize);
  const float cell = field.cell_size;
  // Normals by central differences; horizons by the terrain system's sweep.
  std::vector<glm::vec3> normals(static_cast<std::size_t>(kSize) * kSize);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int x0 = std::max(x - 1, 0), x1 = std::min(x + 1, kSize - 1);
      const int y0 = std::max(y - 1, 0), y1 = std::min(y + 1, kSize - 1);
      const float dx = (field.at(x1, y) - field.at(x0, y)) / ((x1 - x0) * cell);
      const float dy = (field.at(x, y1) - field.at(x, y0)) / ((y1 - y0) * cell);
      normals[static_cast<std::size_t>(y) * kSize + x] = glm::normalize(glm::vec3(-dx, -dy, 1));
    }
  terrain_shadow::HorizonGrid horizons;
  terrain_shadow::HorizonParams hp;
  hp.azimuths = 32;
  terrain_shadow::sweep_horizons(field, hp, terrain_shadow::TexelRect::all(field), horizons);

  // 400 spheres of radius 30-90 m, centres over the inner 80 x 80 texels, 10-150 m clear of the
  // highest terrain under them.
  std::uint64_t seed = 11;
  std::vector<WorldSphere> spheres;
  while (spheres.size() < 400) {
    const float r = 30 + 60 * uniform01(seed);
    const float cx = (8 + 80 * uniform01(seed)) * cell, cy = (8 + 80 * uniform01(seed)) * cell;
    float top = -std::numeric_limits<float>::max();
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        if (glm::length(glm::vec2(x * cell - cx, y * cell - cy)) < r + cell)
          top = std::max(top, field.at(x, y));
    spheres.push_back({{cx, cy, top + r + 10 + 140 * uniform01(seed)}, r});
  }
  // Receivers: every 4th texel of the inner 65 x 65 (17 x 17).
  std::vector<reference::Receiver> receivers;
  std::vector<std::size_t> texel;
  for (int y = 16; y <= 80; y += 4)
    for (int x = 16; x <= 80; x += 4) {
      const std::size_t i = static_cast<std::size_t>(y) * kSize + x;
      receivers.push_back({{x * cell, y * cell, field.at(x, y)}, normals[i]});
      texel.push_back(i);
    }

  const Sky skies[] = {{"uniform", uniform_sky()}, {hdr_name(), sky_map()}};
  for (const Sky& sky : skies) {
    reference::SceneDesc desc;
    desc.environment = reference::EnvironmentLight{sky.map, 0.0f};
    desc.height_fields.push_back({field, glm::vec3(0.0f)});
    const std::vector<float> terrain_only = reference_irradiance(desc, receivers, 1024);
    for (const WorldSphere& s : spheres) desc.spheres.push_back({s.centre, s.radius, ""});
    const std::vector<float> truth = reference_irradiance(desc, receivers, 1024);
    desc.height_fields.clear();
    desc.spheres.clear();
    const double open_mean = mean(reference_irradiance(desc, receivers, 1024));

    const sh::CoeffsRgb<4> radiance =
        sh::project_equirect<4>(sky.map.rgb.data(), sky.map.width, sky.map.height);
    const TerrainReceivers t{&field, glm::vec3(0.0f), 1.0f, &horizons, &normals};
    const auto run = [&](const std::string& method, const BlockerSettings& s) {
      BlockerAccumulation<4> acc(s);
      acc.set_blockers(spheres);
      const terrain_shadow::LogWedge<4> wedges(hp.azimuths, std::log(s.blocker.epsilon));
      std::vector<glm::vec3> ratio;
      update_terrain_ratios<4>(t, acc, wedges, radiance, ratio);
      std::vector<float> e;
      for (std::size_t i = 0; i < receivers.size(); ++i)
        e.push_back(ratio[texel[i]].y * terrain_only[i]);
      const Errors err = compare(e, truth, open_mean);
      std::printf("| 400 spheres over the DEM, %s | %s | %.2f%% | %.2f%% | | |\n", sky.name,
                  method.c_str(), 100 * err.rms, 100 * err.max);
      return err;
    };
    float deepest = 0, no_blockers = 0;
    for (std::size_t i = 0; i < receivers.size(); ++i) {
      deepest = std::max(deepest, static_cast<float>((terrain_only[i] - truth[i]) / open_mean));
      no_blockers += static_cast<float>(std::pow((terrain_only[i] - truth[i]) / open_mean, 2));
    }
    std::printf(
        "| 400 spheres over the DEM, %s | no blockers at all (the blockers' share) | "
        "%.2f%% | %.2f%% | | |\n",
        sky.name, 100 * std::sqrt(no_blockers / receivers.size()), 100 * deepest);
    const Errors grid = run("default (grid, min_sin 0.05)", {});
    BlockerSettings all;
    all.blocker.min_sin = 0;
    const Errors all_pairs = run("all pairs (min_sin 0)", all);
    EXPECT_GT(deepest, 0.2f);  // the blockers do shadow the terrain
    // Measured: uniform 4.0% (grid) and 6.2% (all pairs) of a 23% share; sky.exr 23% and 24% of
    // a 30% share (the sun's shadows of 400 spheres are far beyond 4 bands).
    const bool uniform = sky.name[0] == 'u';
    EXPECT_LT(grid.rms, uniform ? 0.06f : 0.30f);
    EXPECT_LT(all_pairs.rms, uniform ? 0.09f : 0.30f);
    const float share = std::sqrt(no_blockers / receivers.size());
    EXPECT_LT(grid.rms, (uniform ? 0.3f : 0.9f) * share);  // better than leaving them out
  }
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
