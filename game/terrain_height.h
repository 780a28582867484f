// The ground height under a world (x, y) of a Terrain, bilinear between samples, clamped to the
// field's edges: where the demo's objects (boulders, probe-lit floaters, probes) stand or hover.
// Threading: a pure function of an immutable height field.
#pragma once

#include <algorithm>

#include <glm/vec2.hpp>

#include "penumbra/components/terrain.h"
#include "penumbra/data/height_field.h"

namespace penumbra::game {

inline float terrain_height(const components::Terrain& t, glm::vec2 xy) {
  const data::HeightField& f = *t.heights;
  const glm::vec2 q = (xy - glm::vec2(t.origin)) / f.cell_size;
  const float fx = std::clamp(q.x, 0.0f, static_cast<float>(f.width - 1));
  const float fy = std::clamp(q.y, 0.0f, static_cast<float>(f.height - 1));
  const int x0 = std::min(static_cast<int>(fx), f.width - 2);
  const int y0 = std::min(static_cast<int>(fy), f.height - 2);
  const float ax = fx - x0, ay = fy - y0;
  const float h = (1 - ay) * ((1 - ax) * f.at(x0, y0) + ax * f.at(x0 + 1, y0)) +
                  ay * ((1 - ax) * f.at(x0, y0 + 1) + ax * f.at(x0 + 1, y0 + 1));
  return t.origin.z + t.height_scale * h;
}

}  // namespace penumbra::game
