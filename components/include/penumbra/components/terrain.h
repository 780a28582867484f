// Terrain component: a height field placed in the world, and its albedo.
// The heights are shared and immutable: an edit publishes a new HeightField, bumps `version`
// and says which samples it touched (systems/terrain_shadow/terrain_edit.h does all three).
#pragma once

#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

namespace penumbra::data {
struct HeightField;  // penumbra/data/height_field.h
}

namespace penumbra::components {

// Half-open rectangle of height samples [x0, x1) x [y0, y1).
struct SampleRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct Terrain {
  std::shared_ptr<const data::HeightField> heights;
  glm::vec3 origin{0.0f};    // world position of sample (0, 0) at height 0
  glm::vec3 albedo{0.5f};    // linear
  float height_scale = 1.0f;  // world height = origin.z + height_scale * heights->at(x, y)
  // Changes on every edit. `edited` is the samples the edit from version - 1 to `version`
  // changed; readers that saw version - 1 may update just what that region affects, any other
  // reader recomputes everything.
  std::uint64_t version = 0;
  SampleRect edited{};
};

}  // namespace penumbra::components
