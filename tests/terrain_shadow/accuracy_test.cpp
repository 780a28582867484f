// Accuracy of the terrain shadow system (TerrainShadowing: [Meier13] ch. 4, the
// scenes of ch. 6) against the reference integrator (engine/reference), through the support
// library terrain_reference.h (scenes, receivers, ground plane, error definitions).
//
// Two references:
//  - the irradiance reference: E = int L V max(0, n.w) dw by Monte Carlo over the full-resolution
//    map. What the method should produce; its errors are reported for every case and bounded
//    for the default configuration.
//  - the "SH-ideal" (reference_visibility + shade_visibility): the thesis's SH shading
//    ([Meier13] eq. 4.21, 4 bands) fed with the reference's visibility. It shares all SH truncation
//    with the method run with TransferMethod::kTruncatedProduct (the horizon tests below use it),
//    so the method differs from it only through its horizons, azimuth
//    interpolation (eq. 4.15) and wedge table (eq. 4.18). Parameters of the horizon methods
//    change only that part, so their orderings are asserted against it (against the irradiance
//    reference they are confounded: a method that misses occluders adds light and cancels part
//    of the SH truncation's negative bias).
//
// Measured numbers are printed (and recorded as test properties); the bounds below are
// measured values with a margin of about 1.3-1.5x (RelWithDebInfo, the seeds fixed here).
// No test skips: a missing data file throws assets::LoadError and fails the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"
#include "terrain_reference.h"

namespace penumbra::terrain_reference {
namespace {

using terrain_shadow::HorizonMethod;
using terrain_shadow::TerrainShadowConfig;
using terrain_shadow::TerrainShadowing;

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kScale = 1.0f;       // height scale of every scene
constexpr int kStride = 8;           // 32 x 32 receivers at 256 x 256
constexpr float kRotation = 0.7f;    // environment rotation about z (radians), method and reference
constexpr int kSamples = 1024;       // irradiance reference: directions per receiver
constexpr int kIdealSamples = 2048;  // SH-ideal: visibility directions per receiver (2 halves)

// --- Shared inputs (cached for the process: ctest runs each case in its own process, a whole-
// binary run reuses them) ----------------------------------------------------------------------

std::mutex cache_mutex;

std::shared_ptr<const data::HeightField> terrain(std::string_view name) {
  static std::map<std::string, std::shared_ptr<const data::HeightField>, std::less<>> cache;
  std::lock_guard lock(cache_mutex);
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(std::string(name), load_terrain(name, 256)).first;
  return it->second;
}

const data::EnvironmentMap& hdri(std::string_view name) {
  static std::map<std::string, data::EnvironmentMap, std::less<>> cache;
  std::lock_guard lock(cache_mutex);
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(std::string(name), load_hdri(name)).first;
  return it->second;
}

// Irradiance reference of `scene` under hdri `map` rotated by kRotation, at the stride receivers.
const ReferenceIrradiance& environment_reference(std::string_view scene, std::string_view map) {
  static std::map<std::string, ReferenceIrradiance, std::less<>> cache;
  const std::string key = std::string(scene) + "/" + std::string(map);
  {
    std::lock_guard lock(cache_mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  const auto field = terrain(scene);
  Lighting l;
  l.environment = &hdri(map);
  l.rotation_z = kRotation;
  ReferenceOptions o;
  o.samples = kSamples;
  ReferenceIrradiance r =
      reference_irradiance(*field, kScale, texel_receivers(*field, kScale, kStride), l, o);
  std::lock_guard lock(cache_mutex);
  return cache.emplace(key, std::move(r)).first->second;
}

// --- Helpers ----------------------------------------------------------------------------------

std::shared_ptr<data::HeightField> flat_field(int n) {
  auto f = std::make_shared<data::HeightField>();
  f->width = f->height = n;
  f->cell_size = 1.0f;
  f->heights.assign(static_cast<std::size_t>(n) * n, 0.0f);
  f->source = "flat " + std::to_string(n);
  return f;
}

std::vector<glm::vec3> shade(const TerrainShadowing<4>& ts, const sh::CoeffsRgb<4>& radiance) {
  std::vector<glm::vec3> e;
  ts.shade_environment(radiance, e);
  return e;
}

std::vector<glm::vec3> light_only(TerrainShadowing<4>& ts, const reference::SphereLight& light) {
  std::vector<glm::vec3> e;
  ts.add_spherical_light(light.center, light.radius, light.radiance, e);
  return e;
}

// The estimates of `values` at `texels` as exact numbers (for comparing two method results).
std::vector<reference::RgbEstimate> as_reference(const std::vector<glm::vec3>& values,
                                                 const std::vector<std::size_t>& texels) {
  std::vector<reference::RgbEstimate> out(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) out[i].mean = values[texels[i]];
  return out;
}

// Mean of channel sums at the texels (for shadowed fractions).
double mean_at(const std::vector<glm::vec3>& e, const std::vector<std::size_t>& texels) {
  double s = 0;
  for (std::size_t t : texels) s += static_cast<double>(e[t].x) + e[t].y + e[t].z;
  return s / static_cast<double>(texels.size());
}
double mean_of(const std::vector<reference::RgbEstimate>& r) {
  double s = 0;
  for (const auto& e : r) s += static_cast<double>(e.mean.x) + e.mean.y + e.mean.z;
  return s / static_cast<double>(r.size());
}

// Prints one line and records rel_rms / max_rel as properties of the running test.
void report(const std::string& what, const ErrorSummary& e) {
  std::printf("  %-52s %s\n", what.c_str(), format(e).c_str());
  std::string key = what;
  std::replace_if(
      key.begin(), key.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); },
      '_');
  ::testing::Test::RecordProperty(key + "_rel_rms", std::to_string(e.rel_rms));
  ::testing::Test::RecordProperty(key + "_max_rel", std::to_string(e.max_rel));
}

TerrainShadowConfig config(HorizonMethod m, int azimuths, int level_step = 4,
                           float level_offset = 2) {
  TerrainShadowConfig c;
  c.method = m;
  c.azimuths = azimuths;
  c.pyramid.level_step = level_step;
  c.march.level_offset = level_offset;
  return c;
}

// Brute-force horizons (kTexelRays) at the receiver texels only, then the system's own
// visibility and transfer (wedge table, eq. 4.19; transfer, eq. 4.21), exactly as
// TerrainShadowing::compute_transfer does for every texel with kTruncatedProduct:
// TerrainShadowing with kBruteForce at these texels for 1/64 of its cost (a full 256^2 brute-force
// update takes 1.5-3 s).
std::vector<glm::vec3> brute_force_environment(const data::HeightField& f, const ReceiverSet& rs,
                                               int azimuths, const sh::CoeffsRgb<4>& radiance) {
  terrain_shadow::HorizonParams p;
  p.azimuths = azimuths;
  p.height_scale = kScale;
  p.clamp_at_zero = true;
  terrain_shadow::HorizonGrid grid;
  const terrain_shadow::WedgeTable<4> table(azimuths, terrain_shadow::WedgeDomain::kHemisphere,
                                            TerrainShadowConfig{}.table_resolution);
  std::vector<glm::vec3> e(static_cast<std::size_t>(f.width) * f.height, glm::vec3(0.0f));
  for (std::size_t i = 0; i < rs.texels.size(); ++i) {
    const int x = static_cast<int>(rs.texels[i] % f.width),
              y = static_cast<int>(rs.texels[i] / f.width);
    terrain_shadow::brute_force_horizons(f, p, {x, y, x + 1, y + 1}, grid);
    const sh::Coeffs<4> t = terrain_shadow::diffuse_transfer<4>(table.visibility(grid.texel(x, y)),
                                                                rs.receivers[i].normal);
    e[rs.texels[i]] = {sh::dot<4>(radiance[0], t), sh::dot<4>(radiance[1], t),
                       sh::dot<4>(radiance[2], t)};
  }
  return e;
}

// --- The library itself -----------------------------------------------------------------------

// The receivers are the system's texels: same positions and normals (the comparison is texel by
// texel, so a half-texel offset or a different normal would be a modelling error of its own).
TEST(TerrainReference, ReceiversAreTheSystemsTexels) {
  for (std::string_view name : {"dem", "egg_tray"}) {
    const auto field = terrain(name);
    ASSERT_EQ(field->width, 256);
    ASSERT_EQ(field->height, 256);
    TerrainShadowing<4> ts;
    ts.update(field, kScale);
    const ReceiverSet rs = texel_receivers(*field, kScale, kStride);
    ASSERT_EQ(rs.receivers.size(), 32u * 32u);
    for (std::size_t i = 0; i < rs.texels.size(); ++i) {
      const int x = static_cast<int>(rs.texels[i] % 256), y = static_cast<int>(rs.texels[i] / 256);
      EXPECT_EQ(rs.receivers[i].position, ts.position(x, y)) << name << " " << x << "," << y;
      EXPECT_LT(glm::length(rs.receivers[i].normal - ts.normals()[rs.texels[i]]), 1e-6f) << name;
    }
  }
  // Every scene loads at the documented size; an unknown one throws.
  for (std::string_view name : kTerrainNames) EXPECT_EQ(terrain(name)->heights.size(), 65536u);
  EXPECT_EQ(load_terrain("dem", 512)->width, 512);
  EXPECT_THROW(load_terrain("teddy", 256), std::invalid_argument);
}

// --- Default configuration (sweep, 32 azimuths, 4 bands) under two HDR maps -------------------
//
// Maps: sky.exr (hard sun at 48 degrees elevation carrying 53% of the map's luminous power) and
// sunset.exr (sun at 3 degrees, 2% of the power: a soft, warm, low sky). Both rotated 0.7 rad.
//
// What limits the error (decomposition measured on these scenes, sky / sunset; terrain_band_study
// and docs/terrain_shadow.md, "SH bands"):
//  - SH truncation of the radiance to 4 bands: the default transfer is the exact projection of
//    V max(0, n.w) (TransferMethod::kExact), so this is nearly all of it: the same shading at 12
//    bands is 1.1-1.8% / 0.7-1.0% from the reference (its noise 0.9% / 0.6-0.8%); at 4 bands
//    2.8-5.1% / 1.9-3.6%. The sun of sky.exr rings: 4 bands are worse than 3 there whatever
//    the transfer (1.9-2.6% at 3 bands).
//  - the thesis's truncated product V x C (eq. 4.21, kTruncatedProduct) cost 0.2-2.5 points more
//    (4.2-7.0% / 3.5-6.2% at 4 bands; flat, unoccluded ground 1-2% too dark): no longer in the
//    default.
//  - the visibility itself (horizons, azimuth interpolation, wedge table, the sweep's texel-line
//    interpolation): against the SH-ideal the sweep is at the reference's noise floor (about
//    0.3% rms beyond it), 128 azimuths instead of 32 change rel_rms by < 0.1%, a wedge table of
//    8 x 8 instead of 64 x 64 by < 0.05%, and brute-force horizons agree with the sweep to 0.2%.
// So the bounds are SH bounds (the radiance's): more azimuths or finer tables would not tighten
// them. Bounds: the measured values (before the exact transfer in brackets) times about 1.4.
struct EnvBound {
  std::string_view scene, map;
  double rel_rms, max_rel;  // bounds (measured in the comment)
};
constexpr EnvBound kEnvBounds[] = {
    {"dem", "sky", 0.042, 0.12},              // 2.99%, 8.7% (4.21%, 11.3%)
    {"mountains", "sky", 0.043, 0.13},        // 3.03%, 9.5% (4.47%, 13.9%)
    {"cones", "sky", 0.044, 0.26},            // 3.10%, 19.2% (4.34%, 24.4%: shadowed flanks)
    {"sine_grating", "sky", 0.039, 0.092},    // 2.76%, 6.6% (2.97%, 6.7%)
    {"egg_tray", "sky", 0.071, 0.15},         // 5.08%, 10.6% (7.01%, 14.0%)
    {"dem", "sunset", 0.039, 0.11},           // 2.75%, 7.7% (5.02%, 12.4%)
    {"mountains", "sunset", 0.042, 0.123},    // 3.00%, 8.8% (5.47%, 13.3%)
    {"cones", "sunset", 0.035, 0.17},         // 2.47%, 12.2% (3.50%, 15.7%)
    {"sine_grating", "sunset", 0.031, 0.05},  // 1.95%, 3.5% (4.11%, 6.8%)
    {"egg_tray", "sunset", 0.05, 0.126},      // 3.60%, 9.0% (6.18%, 12.6%)
};

void default_configuration_under_two_hdr_maps(std::string_view name) {
  const auto field = terrain(name);
  TerrainShadowing<4> ts;  // defaults: sweep, 32 azimuths, 64 x 64 wedge table
  ts.update(field, kScale);
  for (std::string_view map : {"sky", "sunset"}) {
    const ReferenceIrradiance& ref = environment_reference(name, map);
    const ErrorSummary e =
        compare(shade(ts, environment_sh<4>(hdri(map), kRotation)), ref.texels, ref.environment);
    report(std::string(name) + " " + std::string(map) + " sweep n32", e);
    const EnvBound* b = nullptr;
    for (const EnvBound& c : kEnvBounds)
      if (c.scene == name && c.map == map) b = &c;
    ASSERT_NE(b, nullptr);
    EXPECT_LT(e.rel_rms, b->rel_rms) << name << " " << map;
    EXPECT_LT(e.max_rel, b->max_rel) << name << " " << map;
    // The reference's own error bars are small against the tolerance, with enough dof.
    EXPECT_LT(e.ref_rel_se, b->rel_rms / 4) << name << " " << map;
    EXPECT_LT(e.ref_max_se, b->max_rel / 4) << name << " " << map;
    EXPECT_GE(e.min_dof, 30u);
    // SH truncation darkens (bias -0.8 to -1.4% measured; -0.6 to -5.2% with the truncated
    // product), never brightens by much.
    EXPECT_LT(e.bias, 0.01) << name << " " << map;
    EXPECT_GT(e.bias, -0.03) << name << " " << map;
  }
  // Rotation convention: the method turns its SH radiance with sh::rotate_z exactly as the
  // reference turns the map. The opposite sign (measured 17.6-39.8%) or none (10.1-29.0%) is
  // far worse under the sunny map than the right one (2.8-5.1%), so a convention slip shows.
  const ReferenceIrradiance& ref = environment_reference(name, "sky");
  const double right =
      compare(shade(ts, environment_sh<4>(hdri("sky"), kRotation)), ref.texels, ref.environment)
          .rel_rms;
  for (float wrong : {-kRotation, 0.0f}) {
    const double w =
        compare(shade(ts, environment_sh<4>(hdri("sky"), wrong)), ref.texels, ref.environment)
            .rel_rms;
    EXPECT_GT(w, 2 * right) << name << ": rotation " << wrong << " instead of " << kRotation;
  }
}

// --- The band count (issue 20; docs/terrain_shadow.md, "SH bands") ---------------------------
//
// With the exact transfer (TransferMethod::kExact, the default) the error under sunset falls with
// every band from 3 to 6 on the cones and the sine grating (measured 3.00 / 2.47 / 1.67 / 1.33%
// and 2.37 / 1.95 / 1.43 / 1.21%); the thesis's truncated product (kTruncatedProduct) rises from
// 3 to 4 bands there (2.83 -> 3.50%, 2.80 -> 4.11%) and from 5 to 6 on the grating (1.12 ->
// 1.62%). Under sky.exr (a hard sun) the radiance's own truncation is not monotonic, whatever the
// transfer (terrain_band_study): not asserted here.
template <int N>
double band_error(std::string_view name, terrain_shadow::TransferMethod transfer) {
  TerrainShadowConfig c;
  c.transfer = transfer;
  TerrainShadowing<N> ts(c);
  ts.update(terrain(name), kScale);
  std::vector<glm::vec3> e;
  ts.shade_environment(environment_sh<N>(hdri("sunset"), kRotation), e);
  const ReferenceIrradiance& ref = environment_reference(name, "sunset");
  const ErrorSummary s = compare(e, ref.texels, ref.environment);
  report(std::string(name) + " sunset " + std::to_string(N) + " bands " +
             terrain_shadow::to_string(transfer),
         s);
  return s.rel_rms;
}

TEST(BandCount, ErrorFallsFrom3To6BandsWithTheExactTransfer) {
  using terrain_shadow::TransferMethod;
  for (std::string_view name : {"cones", "sine_grating"}) {
    const double e[] = {
        band_error<3>(name, TransferMethod::kExact), band_error<4>(name, TransferMethod::kExact),
        band_error<5>(name, TransferMethod::kExact), band_error<6>(name, TransferMethod::kExact)};
    for (int i = 0; i + 1 < 4; ++i)
      EXPECT_LT(e[i + 1], e[i] - 0.001) << name << ": " << i + 4 << " bands against " << i + 3;
    // The cause: the truncated product rises from 3 to 4 bands, and the exact 4 bands beat it.
    const double old3 = band_error<3>(name, TransferMethod::kTruncatedProduct);
    const double old4 = band_error<4>(name, TransferMethod::kTruncatedProduct);
    EXPECT_GT(old4, old3 + 0.005) << name;
    EXPECT_LT(e[1], old3) << name;
  }
}

// --- One spherical light above the terrain -------------------------------------------------
//
// A light of radius 5% of the extent, centred above the field at (max height + extent / 2): seen
// from every receiver at >= 35 degrees elevation, 5-6 degrees across, never occluded. Both light
// shadings of the system:
//  - kCapHorizon (the system's default when written): the cap's cosine-weighted solid angle above
//    the horizon and the tangent plane, integrated directly (cap_transfer.h), with its default
//    radial-sweep horizons and with the march. Exact up to its chord quadrature: measured
//    0.00-0.01% rel_rms, max 0.05%, for both.
//  - kShWedges ([Meier13] eq. 4.22-4.29), march horizons (ls 4, lo 2, 16 azimuths): sphere wedge
//    table, light cap in 4-band SH (eq. 4.27),
//    E = L_cap . (V x C). Limited by 4-band SH of a small cap times the clamped cosine: the
//    same SH shading fed with the reference's visibility is 8.3-13.5% rel_rms from the
//    reference, the method 7.1-12.8%, and the two within 1.8-2.8% of each other (noise 1.6%).
//    On flat ground 4 bands give -8% to +6% for lights 20-90 degrees up, far worse near grazing
//    incidence (GrazingLight); steep flanks turned away from the light see it near grazing
//    incidence, hence the larger max_rel on the egg tray and the sine grating.
struct LightBound {
  std::string_view scene;
  double rel_rms, max_rel;  // kShWedges bounds (measured in the comment)
};
constexpr LightBound kShLightBounds[] = {
    {"dem", 0.11, 0.45},           // 8.02%, 33.7%
    {"mountains", 0.10, 0.40},     // 7.14%, 29.0%
    {"cones", 0.10, 0.45},         // 7.14%, 33.2%
    {"sine_grating", 0.15, 0.54},  // 11.2%, 40.1%
    {"egg_tray", 0.17, 0.68},      // 12.8%, 50.8%
};

reference::SphereLight overhead_light(const data::HeightField& f) {
  const float extent = static_cast<float>(f.width - 1) * f.cell_size;
  const float top = *std::max_element(f.heights.begin(), f.heights.end()) * kScale;
  reference::SphereLight l;
  l.center = {0.5f * extent, 0.5f * extent, top + 0.5f * extent};
  l.radius = 0.05f * extent;
  l.radiance = {3.0f, 2.5f, 2.0f};
  l.name = "overhead";
  return l;
}

// kShWedges takes its horizons from light_method (march or brute force), kCapHorizon from
// cap_method (radial sweep, march or rays).
TerrainShadowConfig light_config(terrain_shadow::CapHorizons method) {
  TerrainShadowConfig c;
  c.light_shading = terrain_shadow::LightShading::kCapHorizon;
  c.cap_method = method;
  return c;
}
TerrainShadowConfig light_config(terrain_shadow::LightWedgeHorizons method) {
  TerrainShadowConfig c;
  c.light_shading = terrain_shadow::LightShading::kShWedges;
  c.light_method = method;
  return c;
}

void overhead_light_accuracy(std::string_view name) {
  using terrain_shadow::LightShading;
  const auto field = terrain(name);
  const ReceiverSet rs = texel_receivers(*field, kScale, kStride);
  const reference::SphereLight light = overhead_light(*field);
  Lighting l;
  l.lights = {light};
  ReferenceOptions o;
  o.samples = kSamples;
  const ReferenceIrradiance ref = reference_irradiance(*field, kScale, rs, l, o);

  for (terrain_shadow::CapHorizons m :
       {terrain_shadow::CapHorizons::kRadialSweep, terrain_shadow::CapHorizons::kMarch}) {
    TerrainShadowing<4> cap(light_config(m));
    cap.update(field, kScale);
    const ErrorSummary c = compare(light_only(cap, light), ref.texels, ref.lights);
    report(std::string(name) + " overhead light, cap_horizon " + terrain_shadow::to_string(m), c);
    EXPECT_LT(c.rel_rms, 0.005) << name;
    EXPECT_LT(c.max_rel, 0.01) << name;
  }

  TerrainShadowing<4> wedges(light_config(terrain_shadow::LightWedgeHorizons::kMarch));
  wedges.update(field, kScale);
  const ErrorSummary w = compare(light_only(wedges, light), ref.texels, ref.lights);
  report(std::string(name) + " overhead light, sh_wedges march n16", w);
  const LightBound* b = nullptr;
  for (const LightBound& x : kShLightBounds)
    if (x.scene == name) b = &x;
  ASSERT_NE(b, nullptr);
  EXPECT_LT(w.rel_rms, b->rel_rms) << name;
  EXPECT_LT(w.max_rel, b->max_rel) << name;
  EXPECT_LT(std::fabs(w.bias), 0.06) << name;  // +1.6 to +4.0% measured
  EXPECT_LT(w.ref_rel_se, 0.001);
}

// --- Horizon methods and parameters ---------------------------------------------------------
//
// Per scene: sweep at 8/16/32/64 azimuths, brute force at 32, march (ls, lo) = (1, 2), (2, 2),
// (4, 2) (the thesis default), (4, 0) at 32. Each is reported against both references; the
// assertions use the SH-ideal (2048 directions: its own rel_rms noise is 0.8-1.0% under sky and
// 0.4-0.7% under sunset) and only differences the method predicts:
//  - brute force and sweep compute the same horizons up to the sweep's interpolation between
//    lines (horizon_sweep.h): their irradiance agrees to < 0.5% rms (measured 0.06-0.16%, max
//    1.6%) and their rel_rms to 0.25 points (measured <= 0.09);
//  - more azimuths do not make it worse (rel_rms may rise only by 0.15 points of noise; measured
//    sweep n32 0.81-0.87% sky, 0.49-0.62% sunset, i.e. at the noise, and n64 within 0.02);
//  - on the cones (thin features between azimuths, [Meier13] fig. 6.1) 8 azimuths are clearly worse
//    than 64 (1.44% vs 0.84% sky, 1.31% vs 0.49% sunset); elsewhere n8 costs 0.0-0.3 points;
//  - the march samples the terrain at growing distances from a pre-filtered pyramid, so it
//    misses occluders (bias +0.1 to +3.9% against the SH-ideal) and is never better than the
//    exact sweep; a finer level step samples more densely and is never worse than ls = 1 (000
//    fig. 6.2: ls 1 0.95-2.22% sky, 1.63-4.59% sunset; ls 4 0.82-1.01%, 0.81-1.35%); the
//    thesis's ls = 4, lo = 2 stays within kMarchExcess of the sweep (measured <= 0.73 points).
constexpr double kNoise = 0.0015;         // paired rel_rms differences below this are noise
constexpr double kSameHorizons = 0.0025;  // |rel_rms(brute force) - rel_rms(sweep)|
constexpr double kMarchExcess = 0.010;    // march ls4 lo2 n32 rel_rms - sweep n32 rel_rms

void horizon_methods_and_azimuths(std::string_view name) {
  const auto field = terrain(name);
  const ReceiverSet rs = texel_receivers(*field, kScale, kStride);
  ReferenceOptions o;
  o.samples = kIdealSamples;
  const ReferenceVisibility<4> v = reference_visibility<4>(*field, kScale, rs, o);
  struct MapRefs {
    std::string_view map;
    sh::CoeffsRgb<4> radiance;
    std::vector<reference::RgbEstimate> ideal;
    const ReferenceIrradiance* full;
  };
  std::vector<MapRefs> maps;
  for (std::string_view map : {"sky", "sunset"}) {
    const sh::CoeffsRgb<4> l = environment_sh<4>(hdri(map), kRotation);
    maps.push_back({map, l, shade_visibility<4>(v, l), &environment_reference(name, map)});
  }
  // rel_rms against the SH-ideal, by map, for each method label.
  std::map<std::string, std::vector<double>> ideal;
  auto evaluate = [&](const std::string& label, auto&& irradiance_for) {
    for (const MapRefs& m : maps) {
      const std::vector<glm::vec3> e = irradiance_for(m.radiance);
      const ErrorSummary full = compare(e, m.full->texels, m.full->environment);
      const ErrorSummary id = compare(e, v.texels, m.ideal);
      report(std::string(name) + " " + std::string(m.map) + " " + label + " full", full);
      report(std::string(name) + " " + std::string(m.map) + " " + label + " vs SH-ideal", id);
      ideal[label].push_back(id.rel_rms);
    }
  };
  // The SH-ideal shares the thesis's truncated product (shade_visibility: diffuse_transfer), so
  // the horizon methods are judged through the same transfer.
  const auto thesis = [](TerrainShadowConfig c) {
    c.transfer = terrain_shadow::TransferMethod::kTruncatedProduct;
    return c;
  };
  std::vector<glm::vec3> sweep32_sky;
  for (int n : {8, 16, 32, 64}) {
    TerrainShadowing<4> ts(thesis(config(HorizonMethod::kSweep, n)));
    ts.update(field, kScale);
    evaluate(describe(ts.config()), [&](const sh::CoeffsRgb<4>& l) { return shade(ts, l); });
    if (n == 32) sweep32_sky = shade(ts, maps[0].radiance);
  }
  evaluate("brute_force n32",
           [&](const sh::CoeffsRgb<4>& l) { return brute_force_environment(*field, rs, 32, l); });
  const std::pair<int, float> marches[] = {{1, 2.0f}, {2, 2.0f}, {4, 2.0f}, {4, 0.0f}};
  for (auto [ls, lo] : marches) {
    TerrainShadowing<4> ts(thesis(config(HorizonMethod::kMarch, 32, ls, lo)));
    ts.update(field, kScale);
    evaluate(describe(ts.config()), [&](const sh::CoeffsRgb<4>& l) { return shade(ts, l); });
  }

  // Brute force against the sweep, texel by texel.
  const ErrorSummary bs =
      compare(sweep32_sky, rs.texels,
              as_reference(brute_force_environment(*field, rs, 32, maps[0].radiance), rs.texels));
  report(std::string(name) + " sky sweep n32 vs brute_force n32", bs);
  EXPECT_LT(bs.rel_rms, 0.005) << name;
  EXPECT_LT(bs.max_rel, 0.03) << name;

  for (std::size_t m = 0; m < maps.size(); ++m) {
    const std::string where = std::string(name) + " " + std::string(maps[m].map);
    auto at = [&](const char* label) { return ideal.at(label)[m]; };
    EXPECT_LE(at("sweep n16"), at("sweep n8") + kNoise) << where;
    EXPECT_LE(at("sweep n32"), at("sweep n16") + kNoise) << where;
    EXPECT_LE(at("sweep n64"), at("sweep n32") + kNoise) << where;
    EXPECT_LT(std::fabs(at("brute_force n32") - at("sweep n32")), kSameHorizons) << where;
    EXPECT_LE(at("sweep n32"), at("march ls4 lo2 n32") + kNoise) << where;
    EXPECT_LE(at("march ls4 lo2 n32"), at("march ls1 lo2 n32") + kNoise) << where;
    EXPECT_LE(at("march ls4 lo2 n32"), at("sweep n32") + kMarchExcess) << where;
    if (name == "cones") {
      EXPECT_GT(at("sweep n8"), at("sweep n64") + 0.002) << where;
    }
  }
}

// One test case per scene (plain names for ctest).
#define PENUMBRA_SCENE_TESTS(Name, scene)            \
  TEST(EnvironmentAccuracy, Name) {                  \
    default_configuration_under_two_hdr_maps(scene); \
  }                                                  \
  TEST(OverheadLightAccuracy, Name) {                \
    overhead_light_accuracy(scene);                  \
  }                                                  \
  TEST(HorizonMethods, Name) {                       \
    horizon_methods_and_azimuths(scene);             \
  }
PENUMBRA_SCENE_TESTS(Dem, "dem")
PENUMBRA_SCENE_TESTS(Mountains, "mountains")
PENUMBRA_SCENE_TESTS(Cones, "cones")
PENUMBRA_SCENE_TESTS(SineGrating, "sine_grating")
PENUMBRA_SCENE_TESTS(EggTray, "egg_tray")
#undef PENUMBRA_SCENE_TESTS

// --- The ground plane of the reference (terrain_reference.h, MODELLING NOTE) ------------------
//
// Under a constant environment (radiance 1 over the whole sphere, so the map's SH is exact) at
// the receivers on the field's border: with the ground plane the reference models the method's
// clamped horizon ([Meier13] sec. 4.2.1) and the method is within 1.5% rms (measured 0.5-1.0%); a
// bare field lets tilted border receivers see the sky below the horizontal past the edge, so the
// reference is brighter and the method looks 2-6.6% wrong (bias -1.4 to -5.0%). The cones' border
// is flat ground at the field's minimum height, where both agree (nothing can be seen below it).
TEST(TerrainReference, GroundPlaneModelsTheClampedHorizon) {
  const data::EnvironmentMap env = constant_environment(glm::vec3(1.0f));
  const sh::CoeffsRgb<4> radiance = environment_sh<4>(env, 0.0f);
  Lighting l;
  l.environment = &env;
  ReferenceOptions ground, bare;
  ground.samples = bare.samples = kSamples;
  bare.ground_plane = false;
  for (std::string_view name : kTerrainNames) {
    const auto field = terrain(name);
    std::vector<glm::ivec2> border;
    for (int i = 4; i < 256; i += 8) {
      border.push_back({i, 0});
      border.push_back({i, 255});
      border.push_back({0, i});
      border.push_back({255, i});
    }
    const ReceiverSet rs = texel_receivers(*field, kScale, border);
    const auto with = reference_irradiance(*field, kScale, rs, l, ground);
    const auto without = reference_irradiance(*field, kScale, rs, l, bare);
    TerrainShadowing<4> ts;
    ts.update(field, kScale);
    const std::vector<glm::vec3> e = shade(ts, radiance);
    const ErrorSummary g = compare(e, with.texels, with.environment);
    const ErrorSummary b = compare(e, without.texels, without.environment);
    report(std::string(name) + " border, constant sky, ground plane", g);
    report(std::string(name) + " border, constant sky, bare field", b);
    EXPECT_LT(g.rel_rms, 0.015) << name;
    EXPECT_LT(g.max_rel, 0.045) << name;
    if (name == "cones") {
      EXPECT_NEAR(b.rel_rms, g.rel_rms, 0.002);
    } else {
      EXPECT_GT(b.rel_rms, 1.5 * g.rel_rms) << name;
      EXPECT_LT(b.bias, g.bias - 0.004) << name << ": the bare field's reference is brighter";
    }
  }
}

// --- Known failure modes ([Meier13] ch. 6)
// --------------------------------------------------------

// Fig. 6.1: "a cone falls between sampling directions". A thin tall spike (base radius 4 m,
// 48 m high) on flat ground; receivers 13-29 m from it in the 8 directions 22.5 + 45 k degrees,
// so that from each the spike lies half-way between two of the 8 sampled azimuths and spans at
// most +-18 degrees about it (+-3 more for the rounding to texels). Constant sky (the map's SH is
// exact): the error is the spike's missing occlusion. With 8 azimuths no sampled horizon sees the
// spike at all (the method gives exactly the flat-ground irradiance; measured rel_rms 3.9%,
// max 7.6% of the mean, bias +3.5%, where the reference shows up to 7% occlusion); 16 azimuths
// catch it once or twice (1.3%), 32 (0.50%) and 64 (0.36%, max 1.0%: the reference's noise,
// 0.35%) resolve it.
TEST(TerrainFailureModes, ThinConeBetweenSampledAzimuths) {
  PENUMBRA_STABILITY(
      "a thin spike between the sampled azimuths (8 horizon azimuths)",
      "the spike is invisible to every azimuth: too bright next to it (missing occlusion)",
      "more azimuths (64: error below 1/5 of 8's)");
  auto spike = flat_field(256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      spike->at(x, y) = std::max(0.0f, 12.0f * (4.0f - std::hypot(x - 128.0f, y - 128.0f)));
  std::vector<glm::ivec2> texels;
  for (int k = 0; k < 8; ++k) {
    const double a = (22.5 + 45.0 * k) * std::numbers::pi / 180;
    for (int d = 13; d <= 29; d += 2)
      texels.push_back({static_cast<int>(std::lround(128 - d * std::cos(a))),
                        static_cast<int>(std::lround(128 - d * std::sin(a)))});
  }
  const ReceiverSet rs = texel_receivers(*spike, kScale, texels);
  const data::EnvironmentMap env = constant_environment(glm::vec3(1.0f));
  Lighting l;
  l.environment = &env;
  ReferenceOptions o;
  o.samples = 2048;
  const ReferenceIrradiance ref = reference_irradiance(*spike, kScale, rs, l, o);
  const sh::CoeffsRgb<4> radiance = environment_sh<4>(env, 0.0f);

  TerrainShadowing<4> flat_ts(config(HorizonMethod::kSweep, 8));
  flat_ts.update(flat_field(256), kScale);
  const std::vector<glm::vec3> flat_e = shade(flat_ts, radiance);
  std::map<int, ErrorSummary> err;
  for (int n : {8, 16, 32, 64}) {
    TerrainShadowing<4> ts(config(HorizonMethod::kSweep, n));
    ts.update(spike, kScale);
    const std::vector<glm::vec3> e = shade(ts, radiance);
    err[n] = compare(e, ref.texels, ref.environment);
    report("spike between azimuths, constant sky, sweep n" + std::to_string(n), err[n]);
    if (n == 8) {  // the failure's mechanism: the spike is invisible to every sampled azimuth
      for (std::size_t t : rs.texels) EXPECT_NEAR(e[t].x, flat_e[t].x, 1e-4f * flat_e[t].x);
    }
  }
  // The reference sees the spike: up to ~9% less light next to it.
  double darkest = 1;
  for (std::size_t i = 0; i < rs.texels.size(); ++i)
    darkest =
        std::min(darkest, static_cast<double>(ref.environment[i].mean.x / flat_e[rs.texels[i]].x));
  std::printf("  spike: the reference's darkest receiver gets %.3f of the flat ground's light\n",
              darkest);
  EXPECT_LT(darkest, 0.95);
  PENUMBRA_STABILITY_MEASURE("rel. RMS, 8 azimuths", err[8].rel_rms);
  PENUMBRA_STABILITY_MEASURE("rel. RMS, 64 azimuths", err[64].rel_rms);
  EXPECT_GT(err[8].rel_rms, 0.028);
  EXPECT_GT(err[8].max_rel, 0.055);
  EXPECT_GT(err[8].bias, 0.025);  // missing occlusion: too bright
  EXPECT_LT(err[64].rel_rms, 0.008);
  EXPECT_LT(err[64].max_rel, 0.02);
  EXPECT_LT(err[64].rel_rms, err[8].rel_rms / 5);
  EXPECT_LT(err[16].rel_rms, err[8].rel_rms);
  EXPECT_LT(err[64].rel_rms, err[16].rel_rms);
  EXPECT_LT(err[8].ref_rel_se, 0.005);
}

// Fig. 6.2: undersampling in the distance direction. A thin wall (2 cells thick, 16 m high,
// 200 m long) on flat ground; receivers on a strip 1-100 m behind it. The pyramid march samples
// distances d_i with spacing sr^i (sr = 2^(1/ls), eq. 4.4) from levels pre-filtered for that
// spacing (eq. 4.14), so a 2-cell wall between samples is averaged away: with ls = 1 the march
// sees almost none of it beyond ~8 m (measured rel_rms 9.4%, max 31% of the mean irradiance,
// bias +5.9%). A finer level step helps (ls = 4: 6.2%, 16.8%) but does not fix it, since the
// filtered levels still flatten the wall; the line sweep, exact on the grid lines, does (0.79%,
// 2.1%, reference noise 0.57%).
TEST(TerrainFailureModes, ThinWallBetweenMarchSamples) {
  PENUMBRA_STABILITY("a 2-cell wall between the pyramid march's distance samples",
                     "averaged away by the pre-filtered levels: light through the wall (bias > 0)",
                     "the exact line sweep (default); a finer level step only helps");
  auto wall = flat_field(256);
  for (int y = 28; y < 228; ++y)
    for (int x = 100; x < 102; ++x) wall->at(x, y) = 16.0f;
  std::vector<glm::ivec2> texels;
  for (int y = 120; y <= 136; y += 4)
    for (int d = 1; d <= 100; ++d) texels.push_back({101 + d, y});
  const ReceiverSet rs = texel_receivers(*wall, kScale, texels);
  const data::EnvironmentMap env = constant_environment(glm::vec3(1.0f));
  Lighting l;
  l.environment = &env;
  ReferenceOptions o;
  o.samples = kSamples;
  const ReferenceIrradiance ref = reference_irradiance(*wall, kScale, rs, l, o);
  const sh::CoeffsRgb<4> radiance = environment_sh<4>(env, 0.0f);
  auto error = [&](const TerrainShadowConfig& c) {
    TerrainShadowing<4> ts(c);
    ts.update(wall, kScale);
    const ErrorSummary e = compare(shade(ts, radiance), ref.texels, ref.environment);
    report("thin wall, constant sky, " + describe(c), e);
    return e;
  };
  const ErrorSummary ls1 = error(config(HorizonMethod::kMarch, 32, 1, 2));
  const ErrorSummary ls4 = error(config(HorizonMethod::kMarch, 32, 4, 2));
  const ErrorSummary sweep = error(config(HorizonMethod::kSweep, 32));
  PENUMBRA_STABILITY_MEASURE("rel. RMS, march ls 1", ls1.rel_rms);
  PENUMBRA_STABILITY_MEASURE("rel. RMS, line sweep", sweep.rel_rms);
  EXPECT_GT(ls1.rel_rms, 0.065);
  EXPECT_GT(ls1.max_rel, 0.20);
  EXPECT_GT(ls1.bias, 0.04);  // the missed wall lets light through
  EXPECT_LT(ls4.rel_rms, ls1.rel_rms - 0.02);
  EXPECT_GT(ls4.rel_rms, 0.04);
  EXPECT_LT(sweep.rel_rms, 0.012);
  EXPECT_LT(sweep.max_rel, 0.035);
  EXPECT_LT(sweep.rel_rms, ls1.rel_rms / 6);
  EXPECT_LT(sweep.ref_rel_se, 0.008);
}

// --- Local lights ---------------------------------------------------------------------------

// A light partly occluded by a ridge: a Gaussian ridge (16 m high, sigma 3 m) along y on flat
// ground; the light (radius 16 m, centre 32 m past the ridge, 40 m up) seen from a 58 x 64 m
// patch in front of the ridge, 43% of its light blocked by the ridge (reference: mean irradiance
// of the patch with the ridge against the flat patch without it). Measured (rel_rms, max_rel,
// shadowed fraction):
//  - kCapHorizon (direct cap integral, cap_transfer.h) with the exact radial sweep (its default
//    cap_method) or brute-force horizons: 0.65%, 4.1%, 0.433 (one horizon along the light's
//    azimuth), 0.67%, 3.8%, 0.432 with 4 brute-force horizons across the cap. (An earlier state
//    of the system measured 3.2%, 13.7% with one horizon; the bounds keep room for either.)
//  - kCapHorizon fed by the march (ls 4, lo 2): 36%, 93%, 0.28: the pre-filtered pyramid
//    flattens the ridge's crest (as the thin wall in ThinWallBetweenMarchSamples): too much
//    light (bias +27%).
//  - kShWedges ([Meier13] eq. 4.22-4.29), brute force: 30%, 82%, 0.45: 4-band SH cannot hold the
//    shadow's edge. The same SH shading fed with the reference's visibility (SH-ideal) is 30%
//    from the reference too, and within 4% of the method: the SH is the limit, not the horizons.
TEST(TerrainLights, LightPartlyOccludedByARidge) {
  using terrain_shadow::LightShading;
  auto ridge = flat_field(256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      ridge->at(x, y) = 16.0f * std::exp(-(x - 128.0f) * (x - 128.0f) / (2 * 3.0f * 3.0f));
  const auto flat = flat_field(256);
  std::vector<glm::ivec2> texels;
  for (int y = 96; y < 160; y += 4)
    for (int x = 64; x < 122; x += 2) texels.push_back({x, y});
  const ReceiverSet rs = texel_receivers(*ridge, kScale, texels);
  const ReceiverSet rs_flat = texel_receivers(*flat, kScale, texels);
  reference::SphereLight light;
  light.center = {160.0f, 128.0f, 40.0f};
  light.radius = 16.0f;
  light.radiance = glm::vec3(1.0f);
  Lighting l;
  l.lights = {light};
  ReferenceOptions o;
  o.samples = kSamples;
  const ReferenceIrradiance ref = reference_irradiance(*ridge, kScale, rs, l, o);
  const ReferenceIrradiance ref_flat = reference_irradiance(*flat, kScale, rs_flat, l, o);
  const double ref_shadowed = 1 - mean_of(ref.lights) / mean_of(ref_flat.lights);
  std::printf("  ridge light: reference shadowed fraction %.3f\n", ref_shadowed);
  EXPECT_GT(ref_shadowed, 0.3);
  EXPECT_LT(ref_shadowed, 0.55);

  // Error and shadowed fraction (against the same configuration on the flat field).
  auto run = [&](const TerrainShadowConfig& c, const std::string& what, double* shadowed) {
    TerrainShadowing<4> ts(c), ts_flat(c);
    ts.update(ridge, kScale);
    ts_flat.update(flat, kScale);
    const std::vector<glm::vec3> e = light_only(ts, light);
    *shadowed = 1 - mean_at(e, rs.texels) / mean_at(light_only(ts_flat, light), rs.texels);
    const ErrorSummary s = compare(e, ref.texels, ref.lights);
    report("ridge light, " + what, s);
    std::printf("  %-52s shadowed fraction %.3f\n", what.c_str(), *shadowed);
    return std::pair{s, e};
  };
  double sh_sweep = 0, sh_cap1 = 0, sh_cap4 = 0, sh_march = 0, sh_wedge = 0;
  const ErrorSummary cap_sweep =
      run(light_config(terrain_shadow::CapHorizons::kRadialSweep), "cap_horizon sweep", &sh_sweep)
          .first;
  TerrainShadowConfig c = light_config(terrain_shadow::CapHorizons::kRays);
  const ErrorSummary cap1 = run(c, "cap_horizon brute_force, 1 horizon", &sh_cap1).first;
  c.cap_horizons = 4;
  const ErrorSummary cap4 = run(c, "cap_horizon brute_force, 4 horizons", &sh_cap4).first;
  const ErrorSummary cap_march =
      run(light_config(terrain_shadow::CapHorizons::kMarch), "cap_horizon march ls4 lo2", &sh_march)
          .first;
  const auto [wedge, wedge_e] = run(light_config(terrain_shadow::LightWedgeHorizons::kBruteForce),
                                    "sh_wedges brute_force n16", &sh_wedge);

  EXPECT_LT(cap_sweep.rel_rms, 0.05);
  EXPECT_LT(cap_sweep.max_rel, 0.20);
  EXPECT_NEAR(sh_sweep, ref_shadowed, 0.05);
  EXPECT_LT(cap1.rel_rms, 0.05);
  EXPECT_LT(cap1.max_rel, 0.20);
  EXPECT_LT(cap4.rel_rms, 0.015);
  EXPECT_LT(cap4.max_rel, 0.07);
  EXPECT_LE(cap4.rel_rms, cap1.rel_rms + 0.002);
  EXPECT_NEAR(sh_cap1, ref_shadowed, 0.05);
  EXPECT_NEAR(sh_cap4, ref_shadowed, 0.02);
  // The march sees the ridge, but too low.
  EXPECT_LT(cap_march.rel_rms, 0.45);
  EXPECT_LT(cap_march.max_rel, 1.15);
  EXPECT_GT(sh_march, 0.2);
  EXPECT_LT(wedge.rel_rms, 0.40);
  EXPECT_LT(wedge.max_rel, 1.10);
  EXPECT_NEAR(sh_wedge, ref_shadowed, 0.1);

  // The SH wedge path against the SH-ideal: its horizons are not what limits it.
  o.samples = kIdealSamples;
  const std::vector<reference::RgbEstimate> ideal =
      shade_visibility<4>(reference_visibility<4>(*ridge, kScale, rs, o), light);
  std::vector<glm::vec3> ideal_grid(ridge->heights.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i < rs.texels.size(); ++i) ideal_grid[rs.texels[i]] = ideal[i].mean;
  const ErrorSummary ideal_vs_ref = compare(ideal_grid, ref.texels, ref.lights);
  const ErrorSummary wedge_vs_ideal = compare(wedge_e, rs.texels, ideal);
  report("ridge light, SH-ideal vs reference", ideal_vs_ref);
  report("ridge light, sh_wedges brute_force vs SH-ideal", wedge_vs_ideal);
  EXPECT_GT(ideal_vs_ref.rel_rms, 0.2);  // the 4-band limit itself
  EXPECT_LT(wedge_vs_ideal.rel_rms, 0.05);
}

// [Meier13] fig. 6.1/6.2's cones scene puts its light "at the centre, slightly above the ground",
// so most receivers see it near their horizon. There the thesis's SH path (kShWedges) fails even
// with nothing to occlude: 4 bands of the clamped cosine (eq. 4.29 with V = 1) make a light
// 20 degrees across on flat ground +54% too bright 5 degrees up and +104% 2 degrees up, while
// 20-90 degrees up they are within 6% (measured -5.4%, -3.8%, +6.0%). No horizon parameter
// changes that; the direct cap integral (kCapHorizon) does: within 0.1% at every elevation.
TEST(TerrainLights, GrazingLight) {
  using terrain_shadow::LightShading;
  const auto flat = flat_field(64);
  const std::vector<glm::ivec2> texel = {{32, 32}};
  const ReceiverSet rs = texel_receivers(*flat, kScale, texel);
  TerrainShadowing<4> wedges(light_config(terrain_shadow::LightWedgeHorizons::kMarch));
  TerrainShadowing<4> cap(light_config(terrain_shadow::CapHorizons::kMarch));
  wedges.update(flat, kScale);
  cap.update(flat, kScale);
  for (float deg : {2.0f, 5.0f, 20.0f, 45.0f, 90.0f}) {
    const float e = deg * kPi / 180, dist = 20.0f;
    reference::SphereLight light;
    light.center = {32 + dist * std::cos(e), 32.0f, dist * std::sin(e)};
    light.radius = dist * std::sin(10 * kPi / 180);  // 20 degrees across
    Lighting l;
    l.lights = {light};
    ReferenceOptions o;
    o.samples = 4096;
    const double r = reference_irradiance(*flat, kScale, rs, l, o).lights[0].mean.x;
    const double w = light_only(wedges, light)[rs.texels[0]].x / r - 1;
    const double c = light_only(cap, light)[rs.texels[0]].x / r - 1;
    std::printf("  light %4.0f degrees up on flat ground: sh_wedges %+.3f, cap_horizon %+.4f\n",
                deg, w, c);
    if (deg < 10) {
      EXPECT_GT(w, 0.35) << deg;  // the failure
    } else {
      EXPECT_LT(std::fabs(w), 0.09) << deg;
    }
    EXPECT_LT(std::fabs(c), 0.005) << deg;  // the fix
  }
}

}  // namespace
}  // namespace penumbra::terrain_reference
