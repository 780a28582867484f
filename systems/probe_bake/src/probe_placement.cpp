// Uniform grid placement (probe_placement.h), [Sukys14] sec. 3.1.
#include "penumbra/systems/probe_bake/probe_placement.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::probe_bake {

std::vector<glm::vec3> grid_points(const ProbeVolume& v) {
  if (!(v.spacing > 0) || !std::isfinite(v.spacing))
    throw std::invalid_argument("grid_points: spacing must be finite and > 0");
  int n[3];
  float start[3];
  double total = 1;
  for (int k = 0; k < 3; ++k) {
    const double extent = static_cast<double>(v.max[k]) - v.min[k];
    n[k] = static_cast<int>(std::floor(extent / v.spacing + 1e-6)) + 1;
    start[k] = static_cast<float>(v.min[k] + 0.5 * (extent - (n[k] - 1) * double(v.spacing)));
    total *= n[k];
  }
  if (total > 4e6)
    throw std::invalid_argument("grid_points: " + std::to_string(total) +
                                " points (above 4 M): raise the spacing");
  std::vector<glm::vec3> out;
  out.reserve(static_cast<std::size_t>(total));
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x)
        out.emplace_back(start[0] + x * v.spacing, start[1] + y * v.spacing,
                         start[2] + z * v.spacing);
  return out;
}

}  // namespace penumbra::probe_bake
