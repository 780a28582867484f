// Multi-resolution height pyramid ([Meier13] sec. 4.2.1 and 5.1, eq. 4.4).
// [Interface fixed by the system; see horizon_march.h for how it is sampled.]
//
// Level i is the height field low-pass filtered for a sample spacing of s = sr^i cells,
// sr = 2^(1 / level_step), and stored at the original resolution (decimation, then bicubic
// B-spline reconstruction back to full size), so any level can be sampled at any position.
// n = ceil(level_step * log2(resolution)) + 1 levels (eq. 4.4), resolution = max(width, height).
// Level 0 is the input times height_scale, unfiltered. Level i >= 1: the field tent-filtered
// (half-width s) and decimated to a grid of spacing s anchored at sample 0, then rebuilt at
// every sample by the uniform cubic B-spline of those coefficients ([Meier13] sec. 5.1); both steps
// are separable with clamp-to-edge borders. The effective kernel has a standard deviation of
// about 0.7 s cells. Cost: about 6 multiply-adds per sample and level; memory: n levels.
//
// Threading: build() is not thread-safe; the const accessors may be called concurrently once
// build() has returned.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "penumbra/data/height_field.h"

namespace penumbra::terrain_shadow {

struct PyramidParams {
  int level_step = 4;  // ls >= 1 ([Meier13] eq. 4.4)
};

class HeightPyramid {
 public:
  HeightPyramid() = default;
  // Builds every level. Throws std::invalid_argument (naming field.source) on a field or
  // height_scale the horizon methods reject (horizon.h) or level_step outside [1, 16]. Reuses
  // its storage when rebuilt at the same size.
  void build(const data::HeightField& field, float height_scale, const PyramidParams& params);

  int levels() const { return levels_; }
  int width() const { return width_; }
  int height() const { return height_; }
  float cell_size() const { return cell_size_; }
  int level_step() const { return level_step_; }
  const std::string& source() const { return source_; }  // the field's, for messages
  // Scaled height (metres) of level `level` (0 <= level < levels()) at plane position (x, y) in
  // cells, bilinear, clamped to the border.
  float sample(int level, float x, float y) const;
  // Raw level storage: width * height floats, row-major. The levels lie back to back in one
  // array (level_data(i + 1) == level_data(i) + width * height); the march's vector loops rely
  // on reading a few floats past a level's end.
  const float* level_data(int level) const {
    return data_.data() + static_cast<std::size_t>(level) * width_ * height_;
  }

 private:
  int levels_ = 0, width_ = 0, height_ = 0, level_step_ = 4;
  float cell_size_ = 1.0f;
  std::string source_;
  std::vector<float> data_;     // levels_ * width_ * height_
  std::vector<float> scratch_;  // decimation and reconstruction passes of one level
};

}  // namespace penumbra::terrain_shadow
