#include "penumbra/systems/terrain_shadow/terrain_edit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::terrain_shadow {

EditResult apply_brush(std::shared_ptr<const data::HeightField> field, const Brush& b) {
  if (!field) throw std::invalid_argument("brush: no height field");
  const std::string name = field->source.empty() ? "height field" : field->source;
  if (!std::isfinite(b.centre.x) || !std::isfinite(b.centre.y) || !std::isfinite(b.strength))
    throw std::invalid_argument(name + ": brush centre and strength must be finite");
  if (!(b.radius > 0) || !std::isfinite(b.radius))
    throw std::invalid_argument(name + ": brush radius " + std::to_string(b.radius) +
                                " must be finite and > 0");
  if (b.kind == BrushKind::kSmooth && (b.strength < 0 || b.strength > 1))
    throw std::invalid_argument(name + ": smooth amount " + std::to_string(b.strength) +
                                " must be in [0, 1]");
  const data::HeightField& f = *field;
  const float cs = f.cell_size;
  TexelRect r{std::max(static_cast<int>(std::ceil((b.centre.x - b.radius) / cs)), 0),
              std::max(static_cast<int>(std::ceil((b.centre.y - b.radius) / cs)), 0),
              std::min(static_cast<int>(std::floor((b.centre.x + b.radius) / cs)) + 1, f.width),
              std::min(static_cast<int>(std::floor((b.centre.y + b.radius) / cs)) + 1, f.height)};
  if (r.empty()) return {std::move(field), {}};
  auto out = std::make_shared<data::HeightField>(f);
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const float dx = x * cs - b.centre.x, dy = y * cs - b.centre.y;
      const float q = 1 - (dx * dx + dy * dy) / (b.radius * b.radius);
      if (q <= 0) continue;
      const float falloff = q * q;
      float& h = out->at(x, y);
      switch (b.kind) {
        case BrushKind::kCrater:
          h -= b.strength * falloff;
          break;
        case BrushKind::kRaise:
          h += b.strength * falloff;
          break;
        case BrushKind::kSmooth: {
          float sum = 0;
          int n = 0;
          for (int yy = std::max(y - 1, 0); yy <= std::min(y + 1, f.height - 1); ++yy)
            for (int xx = std::max(x - 1, 0); xx <= std::min(x + 1, f.width - 1); ++xx, ++n)
              sum += f.at(xx, yy);
          h += b.strength * falloff * (sum / n - h);
          break;
        }
      }
    }
  return {std::move(out), r};
}

bool apply_brush(components::Terrain& t, const Brush& brush) {
  if (!t.heights) throw std::invalid_argument("brush: terrain has no heights");
  if (!(t.height_scale != 0) || !std::isfinite(t.height_scale))
    throw std::invalid_argument(t.heights->source +
                                ": brush needs a finite, non-zero height scale");
  Brush local = brush;
  local.centre -= glm::vec2(t.origin.x, t.origin.y);
  if (brush.kind != BrushKind::kSmooth) local.strength /= t.height_scale;
  EditResult e = apply_brush(t.heights, local);
  if (e.changed.empty()) return false;
  t.heights = std::move(e.field);
  t.version += 1;
  t.edited = {e.changed.x0, e.changed.y0, e.changed.x1, e.changed.y1};
  return true;
}

}  // namespace penumbra::terrain_shadow
