// Ground truth for the terrain shadow system: the test scenes, the reference integrator's
// irradiance at a subsampled set of texel receivers, and the error summary that the accuracy
// tests (accuracy_test.cpp) assert on and the benchmark puts on its speed-vs-accuracy chart.
// Library target penumbra_terrain_reference (tests/terrain_shadow/CMakeLists.txt).
//
// Scenes (load_terrain), every one a square size x size field, heights scaled by 1:
//  - "dem": the central size x size crop of ../shared/data/terrain/jacksboro_fault_dem.pgm
//    (74.4 m cells after the loader's resampling; 19 km across and 257-1036 m at 256). Sizes above
//    the DEM's 403 samples resample its central 403 x 403 square bilinearly (finer cells).
//  - "mountains", "cones", "sine_grating", "egg_tray" (and "city"): assets::procedural_scene
//    with its default parameters and seed 1 over a fixed extent of kProceduralExtent = 256 m,
//    whatever the size (cell = 256 / (size - 1) m, about 1 m at 256: the shapes of [Meier13] ch. 6
//    rendered at 256x256). At that extent the slopes are those the generators were designed
//    for, steep enough for long shadows and partly occluded skies everywhere: cone flanks 45
//    degrees (flat plain between them), sine grating and egg tray up to 38 degrees (pi A / P,
//    A = 8 m, P = 32 m; mean 26-28), mountains up to 41 (mean 14); the DEM crop up to 34 (mean
//    14). The thesis gives no extents or heights; these match its images in character.
//
// Reference (reference_irradiance): an Embree scene of the field placed exactly as
// TerrainShadowing places it (sample (0, 0) at the origin, z = height_scale * h), receivers at
// the texels' positions with central-difference normals (TerrainShadowing::position(x, y) and
// normals(), the same as reference::height_field_receivers), the environment map with its
// rotation about z and optionally spherical lights.
//
// MODELLING NOTE, the ground plane: the method clamps the environment horizon at 0 ([Meier13] sec.
// 4.2.1: the terrain is taken to continue beyond its border, so nothing below the horizontal
// plane of a receiver is ever visible), whereas a bare height field in the reference ends at
// its border and a receiver near the border sees sky below the horizontal past it (for tilted
// normals a good part of the cosine lobe). To model the method's assumption the reference scene
// gets, by default, a flat square of two triangles at the field's minimum height, centred on the
// field and ground_extent (1000) times the field's extent wide. From a receiver dh above that
// height the only sky left below the horizontal is a band of elevation about
// dh / (500 * extent): negligible. Directions that are below the horizontal but blocked by the
// field's own terrain are blocked in both. The plane never blocks a spherical light that lies
// wholly above it (a segment between two points above a plane stays above it), so the same
// scene serves lights. With ReferenceOptions::ground_plane = false the bare field is used.
// Measured (accuracy_test.cpp, GroundPlaneModelsTheClampedHorizon: border receivers, constant
// sky, default method): with the plane the method is 0.5-1.0% rel_rms from the reference, with
// the bare field 2.0-6.6% (the bare reference 1.4-5.0% brighter); on the 32 x 32 interior
// receivers the bare field still shifts max_rel by up to 6 points. Ray offsets are fixed to
// 1e-5 x the field's own size (the integrator's automatic offset would scale with the plane).
//
// Errors (compare): over the receivers, with |v| the Euclidean norm of an RGB vector (all three
// channels count, none is singled out):
//   rel_rms  = sqrt(mean |E - E_ref|^2) / sqrt(mean |E_ref|^2)
//   max_rel  = max |E - E_ref| / mean |E_ref|   (relative to the mean, so that dark texels do
//              not explode: a shadowed texel's error counts in units of a typical texel's E)
//   bias     = mean of (E - E_ref) summed over channels / mean of E_ref summed over channels
//   ref_rel_se = sqrt(mean |se|^2) / sqrt(mean |E_ref|^2): the reference's own relative
//              standard error, the rel_rms the reference alone would show against the truth;
//   ref_max_se = max |se| / mean |E_ref|: its counterpart of max_rel.
// A zero reference (all receivers dark) makes the relative errors +infinity unless the method
// is zero there too (then 0), so such a case fails any bound instead of passing it.
// A tolerance on rel_rms means something only while ref_rel_se is far below it; the tests
// assert that too.
//
// Threading: pure functions except load_* (file reads); the reference runs tbb::parallel_for in
// the caller's arena. Errors: a missing or unreadable data file throws assets::LoadError (a test
// that needs it fails, it never skips); an unknown scene name or bad size std::invalid_argument.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::terrain_reference {

// ../shared/data (the PENUMBRA_SHARED_DATA compile definition).
std::filesystem::path shared_data();

inline constexpr float kProceduralExtent = 256.0f;  // metres per side of the procedural scenes
// The scenes of the accuracy tests, in table order.
inline constexpr std::array<std::string_view, 5> kTerrainNames = {"dem", "mountains", "cones",
                                                                  "sine_grating", "egg_tray"};

// A scene by name (see the header comment) at size x size samples (size >= 2).
std::shared_ptr<const data::HeightField> load_terrain(std::string_view name, int size = 256);

// ../shared/data/hdri/<name>.exr.
data::EnvironmentMap load_hdri(std::string_view name);
// A width x height map of one radiance everywhere (the ground plane blocks its lower half).
data::EnvironmentMap constant_environment(glm::vec3 radiance, int width = 64, int height = 32);

// The map's SH projection (sh::project_equirect) turned by rotation_z about +z the way the
// reference turns the map (reference/environment.h, sh::rotate_z): the radiance the method gets.
template <int N>
sh::CoeffsRgb<N> environment_sh(const data::EnvironmentMap& map, float rotation_z);

// Receivers at a subset of the field's texels.
struct ReceiverSet {
  int width = 0, height = 0;        // of the field
  std::vector<std::size_t> texels;  // y * width + x, in the order of `receivers`
  std::vector<reference::Receiver> receivers;
};
// Every stride-th texel along both axes, starting at stride / 2 (so 8 gives 32 x 32 receivers at
// 256 x 256, none on the border row).
ReceiverSet texel_receivers(const data::HeightField& field, float height_scale, int stride);
// Given texels (x, y); throws std::invalid_argument for one outside the field.
ReceiverSet texel_receivers(const data::HeightField& field, float height_scale,
                            std::span<const glm::ivec2> texels);

struct ReferenceOptions {
  int samples = 1024;  // directions per receiver (per light for lights)
  std::uint64_t seed = 1;
  bool ground_plane = true;    // see MODELLING NOTE
  float ground_extent = 1000;  // plane side / field side
};

struct Lighting {
  const data::EnvironmentMap* environment = nullptr;  // not owned; null: no environment
  float rotation_z = 0;
  std::vector<reference::SphereLight> lights;
};

// The reference scene: the field (heights x height_scale), the ground plane if asked, the
// lighting.
reference::SceneDesc reference_scene(const data::HeightField& field, float height_scale,
                                     const Lighting& lighting,
                                     const ReferenceOptions& options = {});

struct ReferenceIrradiance {
  std::vector<std::size_t> texels;                  // as in the ReceiverSet
  std::vector<reference::RgbEstimate> environment;  // empty without an environment
  std::vector<reference::RgbEstimate> lights;       // sum of the lights; empty without lights
};
ReferenceIrradiance reference_irradiance(const data::HeightField& field, float height_scale,
                                         const ReceiverSet& receivers, const Lighting& lighting,
                                         const ReferenceOptions& options = {});

// The reference's visibility, for shading it with the method's own pipeline: V_ref is the
// whole-sphere SH projection of the reference scene's visibility at each receiver
// (reference::visibility_sh, kSphere; with the ground plane, what lies below the horizontal is
// blocked, as in the method's clamped hemisphere), as two independent estimates of
// samples / 2 directions each (seeds seed and seed + 1). Shading it (shade_visibility) gives
// E = L . diffuse_transfer(V_ref, n) ([Meier13] eq. 4.21), which shares every SH truncation with the
// method (of the radiance, of V, of the product V x C): the method differs from it only by its
// visibility (horizon sampling, azimuth interpolation eq. 4.15, wedge table eq. 4.18). The
// horizon methods' parameters are judged against it. Its std_error is |E_a - E_b| / 2 per
// channel (unbiased for the variance of the two estimates' mean; one degree of freedom per
// receiver, so only aggregates over many receivers are meaningful).
template <int N>
struct ReferenceVisibility {
  std::vector<std::size_t> texels;
  std::vector<reference::Receiver> receivers;
  std::vector<sh::Coeffs<N>> half[2];
};
template <int N>
ReferenceVisibility<N> reference_visibility(const data::HeightField& field, float height_scale,
                                            const ReceiverSet& receivers,
                                            const ReferenceOptions& options = {});
// Under an environment (SH radiance, already rotated).
template <int N>
std::vector<reference::RgbEstimate> shade_visibility(const ReferenceVisibility<N>& v,
                                                     const sh::CoeffsRgb<N>& radiance);
// Under one spherical light (its SH cap per receiver, terrain_shadow::spherical_light_radiance):
// what the method would give for the light with exact visibility. (The method's light
// visibility differs on purpose beyond the light's distance, eq. 4.22; V_ref is the whole
// scene's, so this is a diagnostic, not an exact counterpart.)
template <int N>
std::vector<reference::RgbEstimate> shade_visibility(const ReferenceVisibility<N>& v,
                                                     const reference::SphereLight& light);

struct ErrorSummary {
  std::size_t receivers = 0;
  double mean_reference = 0;  // mean |E_ref| (RGB norm), W/m^2
  double rel_rms = 0, max_rel = 0, bias = 0;
  double ref_rel_se = 0, ref_max_se = 0;
  std::uint32_t min_dof = 0;    // smallest nonzero dof of the reference estimates
  std::size_t worst_texel = 0;  // texel index of max_rel
};
// `method` is the method's full grid (width * height, row-major, e.g. from
// TerrainShadowing::shade_environment); `reference` one estimate per texel of `texels`.
ErrorSummary compare(std::span<const glm::vec3> method, std::span<const std::size_t> texels,
                     std::span<const reference::RgbEstimate> reference);
// "rel_rms 3.21% max_rel 10.5% bias -1.20% (ref se 0.31%/1.9%, n 1024)".
std::string format(const ErrorSummary& e);

// "sweep n32", "march ls4 lo2 n32", "brute_force n16" (the environment part of a config).
std::string describe(const terrain_shadow::TerrainShadowConfig& config);

// Method irradiance of the environment for a whole field: update + shade_environment.
template <int N>
std::vector<glm::vec3> method_environment(const terrain_shadow::TerrainShadowConfig& config,
                                          std::shared_ptr<const data::HeightField> field,
                                          float height_scale, const sh::CoeffsRgb<N>& radiance);

}  // namespace penumbra::terrain_reference
