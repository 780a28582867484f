// LightRefresh: which tiles of a terrain a change of its spherical lights makes worth
// re-shading this frame, so a moving light re-shades only what it must and no frame pays for a
// whole light. Ours (the thesis recomputes every light every frame); docs/play.md has the
// measurements.
//
// Criterion. For a light of radiance L and radius r whose centre moves by delta (and whose
// radius or radiance changes), the irradiance E = L int_cap V(w) max(0, n.w) dw of any receiver
// at least d from the path of the centre changes by at most
//     |dE| <= L_max (4 a theta + Omega(r_max, d) - Omega(r_min, d + delta)) + |dL| Omega(r_max, d)
// (light_change_bound): V max(0, n.w) is in [0, 1], so E changes by no more than L times the
// solid angle of the symmetric difference of the two caps; the cap of angular radius
// a = asin(r_max / d) turns by theta <= delta / d, sweeping at most 4 a theta, and its solid
// angle Omega(r, d) = 2 pi (1 - sqrt(1 - (r / d)^2)) changes by at most the radial term. It
// holds whatever the horizon hides. A tile of receivers is stale when the sum of the bounds of
// its lights (luminance), against the lights it was last shaded with, exceeds `tolerance` times
// its darkest texel's total irradiance (environment + lights, from the last frame; at least
// `dark_floor` times the terrain's mean). With the default 1/256 that is below what an 8-bit
// display shows of the texel, and below half the step of its RGBA16F texel.
//
// Spreading. Stale tiles are re-shaded worst first (bound over threshold), at most `budget`
// of the terrain's texels per frame; the rest wait, their bound growing until they come first.
// Tiles never shaded, or whose terrain changed, are stale whatever the bound and come before
// all others (brightest light first). The radial horizon sweep of a light then runs only along
// the lines through the tiles re-shaded (RadialHorizonSweep::run with regions).
//
// Threading: one thread calls everything (the lights system).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

struct LightRefreshConfig {
  int tile = 16;                    // texels per tile side, >= 1
  float tolerance = 1.0f / 256.0f;  // largest missed change, relative to the texel's irradiance
  float dark_floor = 0.01f;         // darkest reference irradiance, relative to the mean
  float budget = 0.25f;             // largest fraction of the texels re-shaded per frame, (0, 1]
};

// A spherical light in the terrain's frame (centre relative to sample (0, 0) at height 0).
struct LightSample {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;
  glm::vec3 radiance{0.0f};
};

// Solid angle of a sphere of radius r seen from distance d (2 pi when d <= r).
float sphere_solid_angle(float radius, float distance);
// Upper bound of the luminance irradiance change, from `before` to `after`, at any receiver at
// least `distance` from the segment between the two centres; infinity when a receiver could be
// inside either sphere.
float light_change_bound(const LightSample& before, const LightSample& after, float distance);
// Upper bound of the luminance irradiance of one light at any receiver `distance` away.
float light_irradiance_bound(const LightSample& light, float distance);

struct LightRefreshStats {
  std::size_t tiles = 0;             // in the terrain
  std::size_t stale = 0;             // over the tolerance this frame
  std::size_t refreshed = 0;         // re-shaded this frame
  float worst_deferred = 0.0f;       // largest bound / threshold of a shaded tile left waiting
  std::size_t unshaded_waiting = 0;  // tiles never shaded (or since the terrain changed) waiting
  // What re-shading really changed (keep_previous + commit), over texels shaded before: the
  // largest change relative to the texel's own irradiance (at least the dark floor), and how
  // many of them changed by more than the tolerance (a wait that showed).
  float worst_observed = 0.0f;
  std::size_t observed_texels = 0, observed_visible = 0;
  std::uint64_t frames_shaded = 0;  // frames that re-shaded anything
};

class LightRefresh {
 public:
  explicit LightRefresh(const LightRefreshConfig& config = {});
  const LightRefreshConfig& config() const { return config_; }

  // Tiles for a width x height grid of receivers at `positions` (row-major); every tile stale.
  // Call again when the terrain changes (the shading of every light may change anywhere).
  void reset(int width, int height, const std::vector<glm::vec3>& positions);
  // The total irradiance each texel showed (row-major, width x height), times `scale`: the
  // reference the tolerance is relative to. Before the first call it is 0 (every change shows).
  void set_reference(const std::vector<glm::vec3>& irradiance, float scale = 1.0f);

  // The tiles to re-shade now for `lights`, worst first, within the budget; empty when nothing
  // changed visibly. The caller re-shades them (all lights, from zero) and calls commit().
  const std::vector<TexelRect>& plan(const std::vector<LightSample>& lights);
  // Optional, between plan() and re-shading: keeps the planned tiles' values of `irradiance`
  // (the lights' sum) so that commit() can measure how much they really changed.
  void keep_previous(const std::vector<glm::vec3>& irradiance);
  // Records that the tiles of the last plan() were shaded with those lights; `irradiance` is
  // the re-shaded sum (for the observed change, after keep_previous).
  void commit(const std::vector<glm::vec3>* irradiance = nullptr);

  const LightRefreshStats& stats() const { return stats_; }

 private:
  struct Tile {
    TexelRect rect;
    glm::vec3 lo{0.0f}, hi{0.0f};   // box of the receivers
    float reference = 0.0f;         // darkest total irradiance (luminance)
    std::uint32_t shaded_with = 0;  // index into snapshots_; kNever: not shaded yet
  };
  static constexpr std::uint32_t kNever = 0xFFFFFFFFu;

  LightRefreshConfig config_;
  int width_ = 0, height_ = 0, tiles_x_ = 0;
  std::vector<Tile> tiles_;
  float mean_reference_ = 0.0f;
  std::vector<float> texel_reference_;               // set_reference(): luminance per texel
  std::vector<std::vector<LightSample>> snapshots_;  // lights tiles were shaded with
  std::vector<LightSample> planned_lights_;
  std::vector<std::size_t> planned_;  // tile indices of the last plan
  std::vector<TexelRect> rects_;
  std::vector<glm::vec3> previous_;  // keep_previous(): the planned tiles' values, in plan order
  LightRefreshStats stats_;
};

}  // namespace penumbra::terrain_shadow
