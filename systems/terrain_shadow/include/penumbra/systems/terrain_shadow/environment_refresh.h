// EnvironmentRefresh: which tiles of a terrain a turn of the environment (its rotation about z)
// and of its key lights makes worth re-shading this frame, so a slowly turning sky re-shades
// only what it must and no frame pays for the whole terrain. Ours, the environment's
// counterpart of LightRefresh (light_refresh.h); docs/play.md has the measurements.
//
// Criterion. A texel's environment irradiance is E = T . R_z(theta) L per channel (T its
// transfer vector, [Meier13] eq. 4.21). R_z turns each SH pair (l, +-m) by m theta, so after a
// turn by dtheta |dE| <= |dtheta| |T| G with G = sqrt(sum_lm m^2 L_lm^2) (the arc bounds the
// chord); in luminance G = sum_c w_c G_c. A key light adds E_k = I max(0, n . d) f, f the share
// of its disc (angular radius a) above the texel's horizon (TerrainShadowing::add_key_light).
// When its direction d turns by an angle delta, n . d changes by at most delta, and f changes
// only for texels whose disc edge comes within delta of their horizon, by at most
// 2 delta / (pi a) (the disc's widest chord over its area); so per tile
//     |dE| <= |dtheta| |T|_max G + sum_k lum(I_k) delta_k (1 + [delta_k >= margin_k] 2 / (pi a_k)),
// margin_k the tile's smallest distance, at its last shading, between a lit-facing texel's
// horizon and the disc's edge (<= 0: a texel was in the penumbra). The bound is compared with
// `tolerance` times the tile's darkest irradiance (environment + key lights + spherical lights
// of the last frame, at least `dark_floor` times the mean), per texel for the SH term.
//
// Spreading. Stale tiles are re-shaded worst first, at most `budget` of the terrain's tiles per
// frame. Tiles never shaded, or whose key-light horizons were swept again (a new
// `horizons_generation`), are stale whatever the bound and come first. When the pose did not
// change since the last frame (settle), tiles still shaded at another pose are re-shaded too,
// within the budget, so a sky that stops converges to a whole shading bit for bit.
//
// Threading: one thread calls everything (the compose system).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

struct EnvironmentRefreshConfig {
  int tile = 16;                    // texels per tile side, >= 1
  float tolerance = 1.0f / 256.0f;  // largest missed change, relative to the texel's irradiance
  float dark_floor = 0.01f;         // darkest reference irradiance, relative to the mean
  float budget = 0.25f;             // largest fraction of the tiles re-shaded per frame, (0, 1]
};

// One key light as the environment shows it this frame.
struct KeyLightPose {
  glm::vec3 direction{0.0f, 0.0f, 1.0f};  // unit, towards the light (world, turned)
  float angular_radius = 0.0f;
  float luminance = 0.0f;           // of its irradiance at normal incidence, W/m^2
  std::span<const float> horizons;  // per texel, as swept for add_key_light
};

// What the environment's shading depends on this frame.
struct EnvironmentPose {
  float rotation = 0.0f;        // EnvironmentLight::rotation_z
  float rotation_speed = 0.0f;  // G above (luminance): rotation_speed_bound() of the SH
  std::vector<KeyLightPose> keys;
  std::uint64_t horizons_generation = 0;  // bumped whenever a key light's horizons are swept
};

// G = sum_c w_c sqrt(sum_lm m^2 L_c,lm^2) of an RGB SH radiance (coefficients l^2 + l + m).
float rotation_speed_bound(std::span<const float> r, std::span<const float> g,
                           std::span<const float> b);

struct EnvironmentRefreshStats {
  std::size_t tiles = 0;        // in the terrain
  std::size_t stale = 0;        // over the tolerance (or unshaded) this frame
  std::size_t refreshed = 0;    // planned this frame
  float worst_deferred = 0.0f;  // largest bound / threshold of a shaded tile left waiting
};

class EnvironmentRefresh {
 public:
  explicit EnvironmentRefresh(const EnvironmentRefreshConfig& config = {});
  const EnvironmentRefreshConfig& config() const { return config_; }

  // Tiles for a width x height grid; transfer_norm[i] = |T_i| (one per texel). Every tile
  // unshaded. Call again when the transfer changes.
  void reset(int width, int height, std::vector<float> transfer_norm);
  // Every tile unshaded (a new map, other key lights): the next plans re-shade them all.
  void invalidate();
  // The total irradiance each texel showed (row-major), times `scale`: what the tolerance is
  // relative to. Before the first call every change shows.
  void set_reference(const std::vector<glm::vec3>& irradiance, float scale = 1.0f);

  // The tiles to re-shade now, worst first, within the budget (`unlimited`: every stale tile).
  // The caller re-shades them at `pose` and calls commit(pose, normals).
  const std::vector<TexelRect>& plan(const EnvironmentPose& pose, bool unlimited = false);
  // Records that the last plan's tiles were shaded at `pose` (normals: per texel, for the key
  // lights' penumbra margins).
  void commit(const EnvironmentPose& pose, const std::vector<glm::vec3>& normals);

  const EnvironmentRefreshStats& stats() const { return stats_; }

 private:
  struct Tile {
    TexelRect rect;
    float transfer_max = 0.0f;  // largest |T| / reference over the tile's texels
    float reference = 0.0f;     // darkest total irradiance (luminance)
    bool shaded = false;
    float rotation = 0.0f;
    std::uint64_t generation = 0;
  };
  float bound_over_threshold(std::size_t tile, const EnvironmentPose& pose) const;

  EnvironmentRefreshConfig config_;
  int width_ = 0, height_ = 0, tiles_x_ = 0;
  std::vector<Tile> tiles_;
  std::vector<float> transfer_norm_;
  // Per tile and key light (tile * max_keys_ + k): its direction and margin when shaded.
  std::size_t max_keys_ = 0;
  std::vector<glm::vec3> key_direction_;
  std::vector<float> key_margin_;
  std::vector<std::size_t> key_count_;  // keys a tile was shaded with
  EnvironmentPose last_pose_;
  bool has_last_pose_ = false;
  std::vector<std::size_t> planned_;
  std::vector<std::pair<float, std::size_t>> candidates_;  // plan(): stale tiles, bound
  std::vector<TexelRect> rects_;
  EnvironmentRefreshStats stats_;
};

}  // namespace penumbra::terrain_shadow
