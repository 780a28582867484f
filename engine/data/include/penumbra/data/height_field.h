// A height field in memory: a regular grid of heights over the xy plane, z up.
// Sample (x, y) sits at world position (x * cell_size, y * cell_size, height(x, y)).
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::data {

struct HeightField {
  int width = 0;           // samples along x
  int height = 0;          // samples along y
  float cell_size = 1.0f;  // metres between neighbouring samples
  std::vector<float> heights;  // width * height, row-major (row = y), metres, all finite
  std::string source;          // file or generator it came from, for messages

  float at(int x, int y) const { return heights[static_cast<std::size_t>(y) * width + x]; }
  float& at(int x, int y) { return heights[static_cast<std::size_t>(y) * width + x]; }
};

// The w x h window of `f` starting at sample (x0, y0), clipped to the field; its source names
// the window. Throws std::invalid_argument when the clipped window is smaller than 1 x 1.
inline HeightField crop(const HeightField& f, int x0, int y0, int w, int h) {
  const int xa = std::max(x0, 0), ya = std::max(y0, 0);
  const int xb = std::min(x0 + w, f.width), yb = std::min(y0 + h, f.height);
  if (xb <= xa || yb <= ya) throw std::invalid_argument(f.source + ": crop window is empty");
  HeightField out;
  out.width = xb - xa;
  out.height = yb - ya;
  out.cell_size = f.cell_size;
  out.heights.reserve(static_cast<std::size_t>(out.width) * out.height);
  for (int y = ya; y < yb; ++y)
    for (int x = xa; x < xb; ++x) out.heights.push_back(f.at(x, y));
  out.source = f.source + " [" + std::to_string(xa) + ".." + std::to_string(xb) + ") x [" +
               std::to_string(ya) + ".." + std::to_string(yb) + ")";
  return out;
}

}  // namespace penumbra::data
