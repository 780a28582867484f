// TerrainBintree: the terrain's level of detail as a right-triangle bintree, a right-triangulated
// irregular network (RTIN; Evans, Kirkpatrick & Townsend 2001), refined per frame against a
// screen-space error budget; plain CPU code, no Vulkan (terrain_pass.h draws what it returns).
//
// The grid of samples is embedded in a virtual square of side 2^k + 1. Its two root triangles
// split at the midpoint of their hypotenuse into two half-size right triangles, down to the
// triangles of one grid cell. A triangle's error is exact: the largest vertical distance between
// a height sample inside it (its edges included) and its plane. A midpoint m carries E(m), the
// largest error of the (up to two) triangles whose hypotenuse it halves and of every midpoint
// below them, and a sphere S(m) around m holding those triangles (their error included) and the
// spheres below. m is active when a vertical error E(m) anywhere in S(m) can span more than the
// budget on screen (projected_pixels). Since E and S grow towards the roots, an active
// midpoint's ancestors are active: both triangles beside an active midpoint are split, and the
// mesh has no T-junction, so no crack and no skirts (the split rule and error propagation of
// ROAM, Duchaineau et al. 1997, and of Mapbox's Martini).
// Every triangle drawn is within the budget: its error is at most E of the inactive midpoint
// that ended its refinement (a cell's two triangles have no error).
//
// Grids that are not 2^k + 1 samples a side: triangles wholly outside the grid are skipped,
// triangles across its border always split (E = infinity) until their pieces are inside or
// outside, so any width and height >= 2 is covered exactly (at the cost of finer triangles
// along the border; 2^k + 1 samples a side, as Unity's heightmaps have, avoid it).
//
// Cost: build() O(n log n) in the virtual samples (the exact errors), 8 bytes per virtual
// sample; triangulate() about 2 nodes per triangle drawn (times: the render benchmark).
// Threading: build() and triangulate() may not overlap; triangulate() is const.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"

namespace penumbra::render {

class TerrainBintree {
 public:
  // In the bintree's frame: sample (x, y) at (x, y, 0) * cell_size + its height.
  struct View {
    glm::mat4 view_proj{1.0f};  // Vulkan clip space (0 <= z <= w): triangles outside are culled
    bool cull = true;
    glm::vec3 eye{0.0f};
    float focal_px = 1.0f;    // pixels per unit of tan(angle) (half the height / tan(fov / 2))
    float max_pixels = 0.0f;  // the budget; <= 0: full detail
  };

  // Errors and bounds of `field`. Fields smaller than 2 x 2 (or with too few heights) give an
  // empty mesh.
  void build(const data::HeightField& field);
  // Appends the mesh's triangles, three sample indices (y * width + x) each, counter-clockwise
  // seen from above; returns the number appended.
  std::size_t triangulate(const View& view, std::vector<std::uint32_t>& indices) const;

  // An upper bound of the pixels a vertical error `error` anywhere in the sphere (centre,
  // radius) spans on screen: error * focal_px * h / d^2, with d the sphere's nearest distance
  // from the eye and h <= d the largest horizontal distance in it (a vertical error seen from
  // above moves less than one seen edge-on); infinity with the eye in the sphere.
  static float projected_pixels(float error, const glm::vec3& centre, float radius,
                                const View& view);

  int size() const { return size_; }  // side of the virtual square, 2^k + 1 (0 when empty)
  // E(m) at virtual midpoint (x, y): 0 where nothing splits there, infinity for border splits.
  float error(int x, int y) const { return error_[static_cast<std::size_t>(y) * size_ + x]; }

 private:
  struct Triangle {
    int ax, ay, bx, by, cx, cy;  // hypotenuse a-b, right angle at c
  };
  template <class Fn>
  void for_each_at_depth(int depth, Fn&& fn) const;
  bool inside(const Triangle& t) const;
  bool outside(const Triangle& t) const;
  glm::vec3 position(int x, int y) const;
  float triangle_error(const Triangle& t) const;
  void refine(const Triangle& t, const View& view, const glm::vec4 (&planes)[6],
              std::vector<std::uint32_t>& indices, std::size_t& count) const;

  int width_ = 0, height_ = 0, size_ = 0, depth_ = 0;
  float cell_ = 1.0f;
  std::vector<float> heights_;  // the field's, width_ x height_
  std::vector<float> error_;    // E(m) per virtual sample
  std::vector<float> radius_;   // radius of S(m) per virtual sample
};

}  // namespace penumbra::render
