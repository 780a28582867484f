#include "penumbra/systems/terrain_shadow/cast_shadow.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "penumbra/systems/terrain_shadow/horizon.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"

namespace penumbra::terrain_shadow {

std::vector<float> point_horizons(const data::HeightField& field, float height_scale,
                                  const glm::vec3& point, int azimuths) {
  HorizonParams p;
  p.azimuths = azimuths;
  p.height_scale = height_scale;
  validate_horizon_input(field, p, {});
  if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z))
    throw std::invalid_argument(field.source + ": cast-shadow point must be finite");
  std::vector<float> angles(azimuths);
  const glm::vec2 start(point.x / field.cell_size, point.y / field.cell_size);
  for (int k = 0; k < azimuths; ++k)  // [Giraud] sec. 4.1: march from the point's own height
    angles[k] = ray_horizon(field, height_scale, start, point.z,
                            static_cast<float>(2.0 * std::numbers::pi * k / azimuths),
                            std::numeric_limits<float>::infinity(), false);
  return angles;
}

template <int N>
sh::Coeffs<N> cast_shadow_log_visibility(const data::HeightField& field, float height_scale,
                                         const glm::vec3& point, const LogWedge<N>& wedges) {
  const std::vector<float> a = point_horizons(field, height_scale, point, wedges.azimuths());
  return wedges.log_visibility(a.data());
}

template <int N>
sh::Coeffs<N> cast_shadow_visibility(const data::HeightField& field, float height_scale,
                                     const glm::vec3& point, const WedgeTable<N>& sphere) {
  if (sphere.domain() != WedgeDomain::kSphere)
    throw std::invalid_argument("cast_shadow_visibility needs a kSphere wedge table");
  const std::vector<float> a = point_horizons(field, height_scale, point, sphere.azimuths());
  return sphere.visibility(a.data());
}

#define PENUMBRA_CAST_SHADOW(N)                                                               \
  template sh::Coeffs<N> cast_shadow_log_visibility<N>(const data::HeightField&, float,     \
                                                       const glm::vec3&, const LogWedge<N>&); \
  template sh::Coeffs<N> cast_shadow_visibility<N>(const data::HeightField&, float,         \
                                                   const glm::vec3&, const WedgeTable<N>&);
PENUMBRA_CAST_SHADOW(3)
PENUMBRA_CAST_SHADOW(4)
PENUMBRA_CAST_SHADOW(5)
#undef PENUMBRA_CAST_SHADOW

}  // namespace penumbra::terrain_shadow
