// Environment light of the reference integrator: an equirectangular RGB radiance map, rotated
// about z, read as a piecewise-constant function over its texels (nearest texel, no filtering),
// with importance sampling of that function.
//
// Convention: penumbra/sh/projection.h (z up; row 0 = zenith, texel (x, y) covers azimuths
// [2 pi x / W, 2 pi (x+1) / W) from +x towards +y and polar angles [pi y / H, pi (y+1) / H)).
// The rotation turns the map by `rotation_z` radians about +z (counter-clockwise seen from
// above): the world radiance is L_world(R_z(rotation_z) w) = L_map(w).
//
// Sampling (PBRT 3rd ed. sec. 13.6.5 / 14.2.4, piecewise-constant 2D distribution): texels are
// chosen with probability proportional to luminance x solid angle (marginal over rows, then
// conditional over columns, by inversion), then a direction uniformly in solid angle inside the
// texel. So the density is pdf(w) = luminance(texel of w) / sum_texels(luminance x solid angle),
// constant over each texel; inversion keeps strata of [0,1)^2 compact (u.y picks the row, u.x
// the column, whose search a guide table shortens: Chen and Asau 1974). Memory: a copy of the
// map plus its density (16 bytes per texel) and the CDFs (about 9 bytes per texel).
// Luminance is Rec. 709 Y = 0.2126 R + 0.7152 G + 0.0722 B; radiance is never negative, so a
// texel with zero luminance is black.
//
// Errors: the constructor throws std::invalid_argument naming the map (its `source`) for a
// non-positive size, an rgb array of the wrong length, a negative or non-finite texel, or a
// non-finite rotation. An all-black map is valid: can_sample() is then false.
// Threading: immutable after construction; every const member is safe from any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/ext/vector_double2.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/luminance.h"

namespace penumbra::reference {

class EnvironmentSampler {
  struct Texel {
    float r, g, b;
    float pdf;  // per steradian
  };

 public:
  EnvironmentSampler(const data::EnvironmentMap& map, float rotation_z);

  struct Lookup {
    glm::vec3 radiance;  // W / (m^2 sr), per channel
    float pdf;           // density of sample() at this direction, per steradian
  };
  // Radiance and sampling density in world direction `dir` (unit length).
  Lookup lookup(const glm::vec3& dir) const { return texel(texel_index(dir)); }
  // The same in two steps (row-major texel index, then its data), so that a caller can compute
  // many indices first and let the memory loads overlap.
  std::size_t texel_index(const glm::vec3& dir) const;
  Lookup texel(std::size_t index) const {
    const Texel& t = texels_[index];
    return {{t.r, t.g, t.b}, t.pdf};
  }

  struct Sample {
    glm::vec3 dir;       // world space, unit length
    glm::vec3 radiance;  // of the texel it was drawn from
    float pdf;           // per steradian, > 0
  };
  // Maps u in [0,1)^2 to a direction. Requires can_sample().
  Sample sample(glm::dvec2 u) const;

  bool can_sample() const { return total_ > 0; }
  int width() const { return width_; }
  int height() const { return height_; }
  // sum over texels of luminance x solid angle (luminous "power" of the map, W/m^2 scale).
  double luminance_integral() const { return total_; }

 private:
  int width_ = 0, height_ = 0;
  float cos_rot_ = 1, sin_rot_ = 0;
  double total_ = 0;
  std::vector<Texel> texels_;    // the map and its density, one 16-byte record per texel
  std::vector<double> row_cdf_;  // height + 1 entries
  std::vector<double> col_cdf_;  // height rows of width + 1 entries
  int guide_size_ = 1;           // per row: guide_[k] = interval holding u = k / guide_size_
  std::vector<std::uint32_t> col_guide_;  // height rows of guide_size_ + 1 entries
  std::vector<double> z_edge_;            // cos(pi y / height), y = 0..height
};

// Rec. 709 luminance (penumbra/data/luminance.h).
using data::luminance;

}  // namespace penumbra::reference
