// Receivers on height fields, and combining independent estimates.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/exponential.hpp>

#include "common.h"

namespace penumbra::reference {

std::vector<Receiver> height_field_receivers(const HeightFieldInstance& placed) {
  const data::HeightField& f = placed.field;
  if (f.width < 2 || f.height < 2 ||
      f.heights.size() != static_cast<std::size_t>(f.width) * f.height || !(f.cell_size > 0)) {
    throw std::invalid_argument(
        "reference::height_field_receivers: height field \"" + f.source +
        "\" needs at least 2x2 samples, matching heights and cell_size > 0");
  }
  std::vector<Receiver> out(f.heights.size());
  for (int y = 0; y < f.height; ++y) {
    const int y0 = y > 0 ? y - 1 : 0, y1 = y + 1 < f.height ? y + 1 : y;
    for (int x = 0; x < f.width; ++x) {
      const int x0 = x > 0 ? x - 1 : 0, x1 = x + 1 < f.width ? x + 1 : x;
      // Central differences (one-sided at the borders): n ~ (-dh/dx, -dh/dy, 1).
      const float dhdx = (f.at(x1, y) - f.at(x0, y)) / ((x1 - x0) * f.cell_size);
      const float dhdy = (f.at(x, y1) - f.at(x, y0)) / ((y1 - y0) * f.cell_size);
      Receiver& r = out[static_cast<std::size_t>(y) * f.width + x];
      r.position = placed.origin + glm::vec3(x * f.cell_size, y * f.cell_size, f.at(x, y));
      r.normal = glm::normalize(glm::vec3(-dhdx, -dhdy, 1.0f));
    }
  }
  return out;
}

RgbEstimate combine(const RgbEstimate& a, const RgbEstimate& b) {
  RgbEstimate out;
  out.mean = a.mean + b.mean;
  out.std_error = glm::sqrt(a.std_error * a.std_error + b.std_error * b.std_error);
  out.samples = a.samples + b.samples;
  out.rays = a.rays + b.rays;
  out.dof = a.dof == 0 ? b.dof : b.dof == 0 ? a.dof : std::min(a.dof, b.dof);
  return out;
}

}  // namespace penumbra::reference
