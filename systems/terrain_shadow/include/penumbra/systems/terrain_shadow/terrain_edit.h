// Terrain edits: brushes that publish a new height field and say which samples they changed,
// so the shadow system recomputes only what the edit can affect (terrain_shadowing.h).
//
// Brushes act on the samples within `radius` of `centre` with a smooth falloff
// f(r) = (1 - (r / radius)^2)^2:
//   kCrater: h -= depth * f (a bowl),  kRaise: h += height * f,
//   kSmooth: h += amount * f * (mean of the 3x3 neighbourhood - h), amount in [0, 1].
// Threading: pure functions; apply_brush(Terrain&) writes the component (a system that calls
// it declares .writes<Terrain>()).
#pragma once

#include <memory>

#include <glm/vec2.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/components/terrain.h"
#include "penumbra/systems/terrain_shadow/horizon.h"

namespace penumbra::terrain_shadow {

enum class BrushKind { kCrater, kRaise, kSmooth };

struct Brush {
  BrushKind kind = BrushKind::kCrater;
  glm::vec2 centre{0.0f};  // plane position, metres (relative to sample (0, 0), or world for
                           // the Terrain overload)
  float radius = 8.0f;     // metres, > 0
  float strength = 2.0f;   // metres (crater depth, raise height) or amount (smooth, 0..1)
};

struct EditResult {
  std::shared_ptr<const data::HeightField> field;  // the new heights
  TexelRect changed;                                 // samples that may differ (may be empty)
};

// Throws std::invalid_argument for a non-finite centre or strength, radius <= 0, or a smooth
// amount outside [0, 1]. A brush entirely off the field changes nothing (empty rect, same
// field pointer).
EditResult apply_brush(std::shared_ptr<const data::HeightField> field, const Brush& brush);

// On a Terrain component: centre in world xy (the terrain's origin is subtracted), heights in
// world metres (divided by height_scale). Publishes the new field, bumps `version` and sets
// `edited`. Returns false when nothing changed.
bool apply_brush(components::Terrain& terrain, const Brush& brush);

}  // namespace penumbra::terrain_shadow
