// Light sources found in an equirectangular HDR map ([Ambrosj16] sec. 4.1, Algorithm 1): the
// brightest blobs (a sun, lamps) as small directional lights, each with the texels it takes out
// of the map; docs/environment.md has the method, the deviations from 003 and the numbers.
//
// Contract: plain data in, plain data out, no ECS. detect_light_sources checks the map
// (check_environment_map: NaN, infinite or negative texels are rejected naming the map and the
// texel) and the settings (std::invalid_argument naming the field), and never fails otherwise:
// an all-black map, a map with no bright region, or fewer bright blobs than requested give
// fewer sources (possibly none) and a `stop` reason. Sources come in the order found (the
// largest cluster mean luminance first, Algorithm 1's Sort); their texel sets are disjoint.
// Directions are unit vectors in Penumbra's z-up frame (penumbra/sh/projection.h).
// Deterministic: the same map and settings give the same result.
// Threading: a pure function of its arguments, single-threaded; independent calls may run
// concurrently.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"

namespace penumbra::environment {

// What k-means measures distances on.
enum class ClusterSpace {
  kUnitDirection,    // unit direction vectors (default): no seam, no polar stretching
  kPixelCoordinates  // [Ambrosj16]'s 2D pixel distance (splits a sun on the longitude seam)
};

// How the first k-means means are chosen. Only deterministic choices exist.
enum class KMeansSeeding {
  kFarthestPoint  // the brightest texel of D^l, then maximin (direction_kmeans.h)
};

// Which D^h texels make a source's halo (its radius and the texels it removes).
enum class HaloSet {
  kConnected,       // default: the 4-connected region of D^h around the light cluster (rows
                    // wrap at the seam and across the poles); radius from its core
  kNearestCentroid  // [Ambrosj16]: D^h texels whose nearest k-means mean is the source's (splits
                    // one blob among the clusters around it; docs/environment.md)
};

// How a halo texel counts in the radius's standard deviation.
enum class RadiusWeight {
  kSolidAngle,  // by its solid angle (default; [Ambrosj16]: every texel alike, on directions)
  kLuminance    // by its luminous energy (prefiltered luminance x solid angle)
};

// What the percentiles count.
enum class PercentileWeight {
  kSolidAngle,  // default: the share of the sphere (a polar sun covers many texels, little sky)
  kTexelCount   // [Ambrosj16]: the share of the texels
};

// Every parameter of the detection; defaults from [Ambrosj16] sec. 4.1 and 5.1.1 where it has
// them, the enums' defaults are Penumbra's deviations (docs/environment.md).
struct DetectionSettings {
  int source_count = 2;            // nLightSources: sources wanted (at most kMaxSources)
  int prefilter_radius = 4;        // Gaussian prefilter radius in texels (sec. 5.1.1)
  float light_percentile = 99.0f;  // lightPercentile: D^l = luminance above this percentile
  float halo_percentile = 96.0f;   // HaloPercentile: D^h (<= light_percentile)
  int min_clusters = 10;           // nLightClusters: k starts at max(this, source_count)
  float radius_sigmas = 3.0f;      // radius = radius_sigmas * max standard deviation
  // HaloSet::kConnected only: the direction and the deviation are taken over the halo texels
  // at least this share of the halo's peak luminance (the source's core; 0.5: its half-maximum
  // region), not over its glow.
  float core_fraction = 0.5f;
  int max_iterations = 100;  // k-means Lloyd steps per source
  // A cluster is a source only if its mean (prefiltered) luminance is at least this multiple
  // of the solid-angle-weighted mean luminance of what is left of the map (the sources found so
  // far blackened): a map with no bright region gives none. Penumbra's, not 003's.
  float min_contrast = 8.0f;
  ClusterSpace cluster_space = ClusterSpace::kUnitDirection;
  KMeansSeeding seeding = KMeansSeeding::kFarthestPoint;
  PercentileWeight percentile_weight = PercentileWeight::kSolidAngle;
  HaloSet halo_set = HaloSet::kConnected;
  RadiusWeight radius_weight = RadiusWeight::kSolidAngle;
};

inline constexpr int kMaxSources = 8;  // 2^8 OEM sets at most

// One source found in the map.
struct DetectedSource {
  glm::vec3 direction{0, 0, 1};  // unit, z-up (eq. 2.4-2.8): the luminous centroid of its
                                 // core (kConnected) or the mean of its light cluster (003)
  float azimuth_deg = 0;         // from +x towards +y, [0, 360)
  float elevation_deg = 0;       // above the horizon (z = 0), [-90, 90]
  float angular_radius = 0;      // radians: radius_sigmas x the largest std deviation of its core
                                 // (kConnected) or halo (003), at least one texel
  float solid_angle = 0;         // steradians of the removed texels
  glm::vec3 irradiance{0};       // sum over the removed texels of RGB radiance x solid angle
  glm::vec3 radiance{0};         // irradiance / solid_angle: the mean RGB radiance
  float energy_share = 0;        // share of the map's luminous energy in the removed texels
  float cluster_share = 0;       // [Ambrosj16]'s luminanceLoss: the light cluster's share
  float peak_contrast = 0;       // cluster mean luminance / remaining mean (see min_contrast)
  int clusters = 0;              // k used when it was found
  int light_texels = 0;          // texels of its light cluster (D^l)
  std::vector<std::uint32_t> texels;  // removed texels (y * width + x), ascending
};

struct LightSourceDetection {
  std::vector<DetectedSource> sources;
  int width = 0, height = 0;
  double total_energy = 0;    // sum of luminance x solid angle over the map (unfiltered)
  double mean_luminance = 0;  // solid-angle-weighted mean luminance (prefiltered map)
  float light_threshold = 0;  // luminance at light_percentile (prefiltered)
  float halo_threshold = 0;   // luminance at halo_percentile (prefiltered)
  int light_texels = 0;       // |D^l| at the start
  int halo_texels = 0;        // |D^h| at the start
  std::string stop;           // why fewer than source_count were found ("" if not)
  double milliseconds = 0;    // wall time of the detection
};

LightSourceDetection detect_light_sources(const data::EnvironmentMap& map,
                                          const DetectionSettings& settings = {});

// Azimuth and elevation (degrees) of a unit direction, as DetectedSource holds them.
void azimuth_elevation(const glm::vec3& dir, float& azimuth_deg, float& elevation_deg);

}  // namespace penumbra::environment
