// Terrain shadowing for one height field, outside the ECS: horizons, per-texel environment
// transfer vectors, and shading by the environment and by spherical lights
// (000_7ffde676d1c99e20.txt sec. 4.2-4.3; the ECS systems in terrain_shadow_systems.h, the
// benchmarks and the accuracy tests all drive this class).
//
// Pipeline per texel (every height sample is a receiver, its normal from central differences
// like reference::height_field_receivers):
//   environment:  horizons (clamped at 0) -> hemisphere wedge table -> V (eq. 4.19)
//                 -> transfer T = V * C(n) (eq. 4.21), stored;  E_env = L_env . T
//   each light:   horizons limited to the light's plane distance, unclamped (eq. 4.22-4.25)
//                 -> sphere wedge table -> V_l -> T_l = V_l * C(n);  E_l = L_cap . T_l (4.29)
// Irradiance E is in W/m^2 per channel; outgoing diffuse radiance is albedo / pi * E.
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
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/assets/height_field.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"

namespace penumbra::terrain_shadow {

enum class HorizonMethod {
  kSweep,       // exact line sweep (default): horizon_sweep.h
  kMarch,       // pyramid march (000 eq. 4.4-4.14): horizon_march.h
  kBruteForce,  // every sample of every texel's ray: tests only
};
const char* to_string(HorizonMethod m);

struct TerrainShadowConfig {
  HorizonMethod method = HorizonMethod::kSweep;  // environment horizons
  int azimuths = 32;                             // n_phi for the environment
  // Local lights need a distance limit, which the sweep lacks: kMarch or kBruteForce.
  HorizonMethod light_method = HorizonMethod::kMarch;
  int light_azimuths = 16;
  PyramidParams pyramid{};  // for kMarch
  MarchParams march{};      // for kMarch
  int table_resolution = 64;
};

struct UpdateStats {
  bool full = false;                // everything was recomputed
  std::size_t horizon_pairs = 0;    // (texel, azimuth) horizons recomputed
  std::size_t transfer_texels = 0;  // transfer vectors recomputed
};

template <int N>
class TerrainShadowing {
 public:
  // Throws std::invalid_argument for a bad configuration (kSweep as light_method, fewer than 3
  // azimuths, ...).
  explicit TerrainShadowing(const TerrainShadowConfig& config = {});

  const TerrainShadowConfig& config() const { return config_; }

  // Full recompute for `field` (validated: NaN heights etc. throw std::invalid_argument naming
  // field->source). Keeps a reference to the field.
  UpdateStats update(std::shared_ptr<const assets::HeightField> field, float height_scale);
  // `field` is the previous field with samples `edited` changed. Falls back to update() when
  // nothing was computed yet, the size or scale changed, or the method is not kSweep.
  UpdateStats update_edit(std::shared_ptr<const assets::HeightField> field, float height_scale,
                          TexelRect edited);

  bool ready() const { return field_ != nullptr; }
  const assets::HeightField& field() const { return *field_; }
  float height_scale() const { return height_scale_; }
  const HorizonGrid& horizons() const { return horizons_; }
  const std::vector<sh::Coeffs<N>>& transfer() const { return transfer_; }
  const std::vector<glm::vec3>& normals() const { return normals_; }
  // Receiver position of texel (x, y) relative to sample (0, 0) at height 0.
  glm::vec3 position(int x, int y) const;

  // irradiance[i] = E_env of texel i for the (already rotated) SH radiance; resized to fit.
  void shade_environment(const sh::CoeffsRgb<N>& radiance,
                         std::vector<glm::vec3>& irradiance) const;
  // irradiance[i] += E of one spherical light (centre relative to sample (0, 0) at height 0).
  // Radius 0, a receiver inside the light, or the light wholly behind the receiver's tangent
  // plane contribute 0. Throws std::invalid_argument for a non-finite or negative input.
  void add_spherical_light(const glm::vec3& centre, float radius, const glm::vec3& radiance,
                           std::vector<glm::vec3>& irradiance);

 private:
  void compute_normals(const TexelRect& r);
  void compute_transfer_rows(const std::vector<unsigned char>* mask);

  TerrainShadowConfig config_;
  WedgeTable<N> hemisphere_;
  WedgeTable<N> sphere_;
  std::shared_ptr<const assets::HeightField> field_;
  float height_scale_ = 1;
  HeightPyramid pyramid_;
  bool pyramid_valid_ = false;
  HorizonGrid horizons_;
  HorizonGrid light_horizons_;  // scratch for add_spherical_light
  std::vector<glm::vec3> normals_;
  std::vector<sh::Coeffs<N>> transfer_;
};

}  // namespace penumbra::terrain_shadow
