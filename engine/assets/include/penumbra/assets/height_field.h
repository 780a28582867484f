// A height field in memory: a regular grid of heights over the xy plane, z up.
// Sample (x, y) sits at world position (x * cell_size, y * cell_size, height(x, y)).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra::assets {

struct HeightField {
  int width = 0;           // samples along x
  int height = 0;          // samples along y
  float cell_size = 1.0f;  // metres between neighbouring samples
  std::vector<float> heights;  // width * height, row-major (row = y), metres, all finite
  std::string source;          // file or generator it came from, for messages

  float at(int x, int y) const { return heights[static_cast<std::size_t>(y) * width + x]; }
  float& at(int x, int y) { return heights[static_cast<std::size_t>(y) * width + x]; }
};

}  // namespace penumbra::assets
