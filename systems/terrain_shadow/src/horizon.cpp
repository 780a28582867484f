#include "penumbra/systems/terrain_shadow/horizon.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace penumbra::terrain_shadow {

void validate_horizon_input(const data::HeightField& field, const HorizonParams& params,
                            const TexelRect& region) {
  const std::string name = field.source.empty() ? std::string("height field") : field.source;
  auto fail = [&](const std::string& why) { throw std::invalid_argument(name + ": " + why); };
  if (field.width < 2 || field.height < 2)
    fail("needs at least 2 x 2 samples, has " + std::to_string(field.width) + " x " +
         std::to_string(field.height));
  if (field.heights.size() != static_cast<std::size_t>(field.width) * field.height)
    fail("has " + std::to_string(field.heights.size()) + " heights for " +
         std::to_string(field.width) + " x " + std::to_string(field.height) + " samples");
  if (!(field.cell_size > 0) || !std::isfinite(field.cell_size))
    fail("cell size " + std::to_string(field.cell_size) + " must be finite and > 0");
  validate_horizon_params(name, params, field.width, field.height, region);
  // Blocks without a branch per sample (this runs at every update and edit); the first
  // non-finite sample is looked for only in a block that has one.
  const std::size_t n = field.heights.size();
  constexpr std::size_t kBlock = 1024;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t e = std::min(n, b + kBlock);
    unsigned bad = 0;  // an exponent of all ones: infinite or NaN
    for (std::size_t i = b; i < e; ++i)
      bad |= (std::bit_cast<std::uint32_t>(field.heights[i]) & 0x7f800000u) == 0x7f800000u;
    if (bad == 0) continue;
    for (std::size_t i = b; i < e; ++i)
      if (!std::isfinite(field.heights[i]))
        fail("height at sample (" + std::to_string(i % field.width) + ", " +
             std::to_string(i / field.width) + ") is not finite");
  }
}

void validate_horizon_params(const std::string& name, const HorizonParams& params, int width,
                             int height, const TexelRect& region) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(name + ": " + why); };
  if (!std::isfinite(params.height_scale))
    fail("height scale " + std::to_string(params.height_scale) + " must be finite");
  if (params.azimuths < 3)
    fail("needs at least 3 azimuths, got " + std::to_string(params.azimuths));
  if (params.limit_to_point &&
      !(std::isfinite(params.limit_to_point->x) && std::isfinite(params.limit_to_point->y)))
    fail("light position must be finite");
  if (region.x0 < 0 || region.y0 < 0 || region.x1 > width || region.y1 > height ||
      region.x0 > region.x1 || region.y0 > region.y1)
    fail("region [" + std::to_string(region.x0) + ", " + std::to_string(region.x1) + ") x [" +
         std::to_string(region.y0) + ", " + std::to_string(region.y1) + ") is outside the field");
}

}  // namespace penumbra::terrain_shadow
