// Terrain shadowing for one height field, outside the ECS: horizons, per-texel environment
// transfer vectors, and shading by the environment and by spherical lights
// ([Meier13] sec. 4.2-4.3; the ECS systems in terrain_shadow_systems.h, the
// benchmarks and the accuracy tests all drive this class).
//
// Pipeline per texel (every height sample is a receiver, its normal from central differences
// like reference::height_field_receivers):
//   environment:  horizons (clamped at 0) -> transfer, stored;  E_env = L_env . T. By
//                 config().transfer: kExact (default, ours): horizons raised to the tangent
//                 plane -> wedge table at N + 1 bands -> V -> T = proj_N(V max(0, n.w))
//                 (transfer.h); kTruncatedProduct (the thesis): wedge table at N bands -> V
//                 (eq. 4.19) -> T = V * C(n) truncated to N bands (eq. 4.21)
//   each light, light_shading = kCapHorizon (default; ours, cap_transfer.h): the horizon
//                 towards the light only, limited to its plane distance (a radial line sweep
//                 from the light's foot: exact; three ray_horizon directions across wide caps
//                 the horizon passes near, see cap_wide) -> E_l = L * int_cap V max(0, n.w) dw,
//                 integrated directly (no SH)
//   each light, kShWedges (the thesis): n_phi horizons limited to the light's plane distance,
//                 unclamped (eq. 4.22-4.25) -> sphere wedge table -> V_l -> T_l = V_l * C(n);
//                 E_l = L_cap . T_l (4.29)
// Irradiance E is in W/m^2 per channel; outgoing diffuse radiance is albedo / pi * E.
//
// Which light shading is faster and more accurate, and by how much: docs/terrain_shadow.md
// ("Light shading, measured").
//
// Dynamic updates: update() recomputes everything; update_edit() only the (texel, azimuth)
// pairs an edit can change (sweep method), then the transfer of texels whose horizons or
// normal changed. Shading reads the stored transfer, so a rotating environment re-shades
// without touching visibility, and lights never touch the environment part.
// Threading: one thread calls the members; each runs tbb::parallel_for over rows of texels in
// the caller's task arena. Const members may run concurrently with each other.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/cap_transfer.h"
#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/light_horizon_march.h"
#include "penumbra/systems/terrain_shadow/radial_horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"

namespace penumbra::terrain_shadow {

// The environment's horizons (TerrainShadowConfig::method).
enum class HorizonMethod {
  kSweep,       // exact line sweep (default): horizon_sweep.h
  kMarch,       // pyramid march ([Meier13] eq. 4.4-4.14): horizon_march.h
  kBruteForce,  // every sample of every texel's ray: tests only
};
const char* to_string(HorizonMethod m);

// kShWedges: a local light's horizons (TerrainShadowConfig::light_method). They need a distance
// limit (the light's), which the parallel sweep lacks, so it is not among them.
enum class LightWedgeHorizons {
  kMarch,       // pyramid march limited to the light's distance ([Meier13] eq. 4.22-4.25)
  kBruteForce,  // every sample of every texel's ray
};
const char* to_string(LightWedgeHorizons h);

// kCapHorizon: the horizon towards the light (TerrainShadowConfig::cap_method).
enum class CapHorizons {
  kRadialSweep,  // exact, every texel at once: radial_horizon_sweep.h (default)
  kMarch,        // pyramid march along the cap's directions: light_horizon_march.h
  kRays,         // ray_horizon along the cap's directions: O(distance) per texel
};
const char* to_string(CapHorizons h);

// How add_spherical_light shades (measurements: the header comment of this file).
enum class LightShading {
  kShWedges,    // [Meier13] eq. 4.22-4.29 (the thesis): light_azimuths horizons by light_method,
                // sphere wedge table, SH transfer, E = L_cap . (V * C(n))
  kCapHorizon,  // ours: the horizon towards the cap only (cap_method), exact cap integral
                // (cap_transfer.h)
};
const char* to_string(LightShading s);

// The environment's transfer (TerrainShadowConfig::transfer). Errors by band count and why:
// docs/terrain_shadow.md ("SH bands").
enum class TransferMethod {
  kExact,             // proj_N(V max(0, n.w)) from V at N + 1 bands (ours; transfer.h)
  kTruncatedProduct,  // [Meier13] eq. 4.21: V_N * C_N truncated to N bands
};
const char* to_string(TransferMethod t);

struct TerrainShadowConfig {
  HorizonMethod method = HorizonMethod::kSweep;      // environment horizons
  int azimuths = 32;                                 // n_phi for the environment
  TransferMethod transfer = TransferMethod::kExact;  // the environment's transfer
  LightShading light_shading = LightShading::kCapHorizon;
  LightWedgeHorizons light_method = LightWedgeHorizons::kMarch;  // kShWedges: horizons of lights
  int light_azimuths = 16;                             // kShWedges: n_phi of the sphere wedge table
  CapHorizons cap_method = CapHorizons::kRadialSweep;  // kCapHorizon: horizon towards a light
  int cap_horizons = 3;  // kCapHorizon: horizon directions across a cap, 1..kMaxCapHorizons
  // kCapHorizon with kRadialSweep: a cap with rho = radius / distance >= cap_wide (near the
  // light) whose centre's horizon passes within twice its half-angle of it takes cap_horizons
  // directions by ray_horizon (O(distance) each: the horizon may vary across a wide cap), any
  // other the sweep's single one; kMarch and kRays take cap_horizons everywhere. Why 0.2:
  // docs/terrain_shadow.md ("Light shading, measured").
  float cap_wide = 0.2f;
  // kCapHorizon: chords of the cap integral, 1..kMaxCapStrips, for caps the tangent plane cuts
  // and caps whose horizon varies; one horizon in front of the plane is closed-form (no strips).
  int cap_strips = 8;
  PyramidParams pyramid{};  // for kMarch
  MarchParams march{};      // for kMarch
  int table_resolution = 64;
};

struct UpdateStats {
  bool full = false;                // everything was recomputed
  std::size_t horizon_pairs = 0;    // (texel, azimuth) horizons recomputed
  std::size_t transfer_texels = 0;  // transfer vectors recomputed
};

// The share of a light's disc (angular radius `angular_radius`, radians) above a horizontal
// line `above` radians below its centre (negative: the line above the centre): the circular
// segment's area over the disc's (small-angle, planar); a step at 0 for a point (radius 0).
float disc_share_above(float above, float angular_radius);

template <int N>
class TerrainShadowing {
 public:
  // Throws std::invalid_argument for a bad configuration (fewer than 3 azimuths, ...).
  explicit TerrainShadowing(const TerrainShadowConfig& config = {});

  const TerrainShadowConfig& config() const { return config_; }

  // Full recompute for `field` (validated: NaN heights etc. throw std::invalid_argument naming
  // field->source). Keeps a reference to the field. Builds the height pyramid only when a
  // kMarch method needs it (the environment's, or the lights' of the chosen light_shading).
  UpdateStats update(std::shared_ptr<const data::HeightField> field, float height_scale);
  // `field` is the previous field with samples `edited` changed. Falls back to update() when
  // nothing was computed yet, the size or scale changed, or the method is not kSweep.
  UpdateStats update_edit(std::shared_ptr<const data::HeightField> field, float height_scale,
                          TexelRect edited);

  bool ready() const { return field_ != nullptr; }
  const data::HeightField& field() const { return *field_; }
  float height_scale() const { return height_scale_; }
  const HorizonGrid& horizons() const { return horizons_; }
  const std::vector<sh::Coeffs<N>>& transfer() const { return transfer_; }
  const std::vector<glm::vec3>& normals() const { return normals_; }
  // Receiver position of texel (x, y) relative to sample (0, 0) at height 0.
  glm::vec3 position(int x, int y) const;

  // irradiance[i] = E_env of texel i for the (already rotated) SH radiance; resized to fit.
  void shade_environment(const sh::CoeffsRgb<N>& radiance,
                         std::vector<glm::vec3>& irradiance) const;
  // The same for the texels of `regions` only (irradiance must already have one value per
  // texel; others are left as they are), bit for bit; parallel over the regions.
  void shade_environment(const sh::CoeffsRgb<N>& radiance, std::vector<glm::vec3>& irradiance,
                         std::span<const TexelRect> regions) const;
  // irradiance[i] += E of one spherical light (centre relative to sample (0, 0) at height 0),
  // shaded as config().light_shading says. Radius 0, a receiver inside the light, or the light
  // wholly behind the receiver's tangent plane contribute 0 (kCapHorizon also gives exactly 0
  // where the horizon hides the whole cap). Throws std::invalid_argument for a non-finite or
  // negative input.
  void add_spherical_light(const glm::vec3& centre, float radius, const glm::vec3& radiance,
                           std::vector<glm::vec3>& irradiance);
  // The same for the texels of `regions` only (irradiance must already have one value per
  // texel; others are left as they are): what add_spherical_light adds there, bit for bit.
  // With kCapHorizon and kSweep the light's horizon sweep runs only along the lines through
  // the regions, each as far as their farthest texel on it (RadialHorizonSweep::run).
  void add_spherical_light(const glm::vec3& centre, float radius, const glm::vec3& radiance,
                           std::vector<glm::vec3>& irradiance, std::span<const TexelRect> regions);

  // A distant light (a sun or lamp found in the environment map, [Ambrosj16] ch. 4) as the
  // terrain's key light, shadowed by the terrain's own horizon in its azimuth (Snyder and
  // Nowrouzezahrai 2008): key_light_horizons sweeps every texel's horizon along the light's
  // azimuth (one line sweep, sweep_direction_horizons, clamped at 0 as the environment's);
  // add_key_light adds to every texel
  //   E = irradiance x max(0, n . direction) x f,
  // f the share of the light's disc (angular radius `angular_radius`) above that horizon: the
  // area of the circular segment above the line at the horizon's elevation (a step for a point).
  // `horizons` must come from key_light_horizons for the same azimuth (add_key_light does not
  // check the azimuth: a caller may keep them while the light moves by less than it can show).
  // Throws std::invalid_argument for a direction that is not finite and unit, a negative or
  // non-finite radius or irradiance, or horizons of another size; before update(), as
  // add_spherical_light.
  void key_light_horizons(const glm::vec3& direction, std::vector<float>& horizons) const;
  void add_key_light(const glm::vec3& direction, float angular_radius, const glm::vec3& irradiance,
                     std::span<const float> horizons, std::vector<glm::vec3>& irradiance_out) const;
  // The same for the texels of `regions` only (irradiance_out has one value per texel), bit for
  // bit.
  void add_key_light(const glm::vec3& direction, float angular_radius, const glm::vec3& irradiance,
                     std::span<const float> horizons, std::vector<glm::vec3>& irradiance_out,
                     std::span<const TexelRect> regions) const;

 private:
  void compute_normals(const TexelRect& r);
  // The transfer of the listed texels (y * width + x), or of all texels where null.
  void compute_transfer(const std::vector<std::size_t>* texels);
  struct Span {  // texels x0 <= x < x1 of row y
    int y, x0, x1;
  };
  void validate_light(const glm::vec3& centre, float radius, const glm::vec3& radiance) const;
  bool span_lit(const Span& s, const glm::vec3& centre, float radius) const;
  void add_sh_light(const glm::vec3& centre, float radius, const glm::vec3& radiance,
                    std::vector<glm::vec3>& irradiance, const std::vector<Span>& spans);
  void add_cap_light(const glm::vec3& centre, float radius, const glm::vec3& radiance,
                     std::vector<glm::vec3>& irradiance, const std::vector<Span>& spans,
                     float reach, std::span<const TexelRect> regions);

  TerrainShadowConfig config_;
  std::optional<WedgeTable<N>> hemisphere_;            // kTruncatedProduct
  std::optional<WedgeTable<N + 1>> hemisphere_exact_;  // kExact
  AzimuthFrame frame_;                                 // kExact: the environment's azimuths
  WedgeTable<N> sphere_;
  std::shared_ptr<const data::HeightField> field_;
  float height_scale_ = 1;
  HeightPyramid pyramid_;
  bool pyramid_valid_ = false;
  HorizonGrid horizons_;
  SweepWorkspace sweep_;                   // the environment sweep's buffers (update, update_edit)
  std::vector<unsigned char> edit_flags_;  // update_edit's changed texels; zero between calls
  HorizonGrid light_horizons_;             // scratch for add_spherical_light (kShWedges)
  RadialHorizonSweep radial_;              // scratch for add_spherical_light (kCapHorizon, kSweep)
  std::vector<glm::vec3> normals_;
  std::vector<sh::Coeffs<N>> transfer_;
};

}  // namespace penumbra::terrain_shadow
