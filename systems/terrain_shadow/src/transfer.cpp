// Diffuse transfer and spherical-light radiance ([Meier13] eq. 4.20-4.21,
// 4.27-4.29, appendix A.1). Pure functions, safe to call from any thread.
#include "penumbra/systems/terrain_shadow/transfer.h"

#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>

#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"

namespace penumbra::terrain_shadow {

template <int N>
sh::Coeffs<N> diffuse_transfer(const sh::Coeffs<N>& visibility, const glm::vec3& normal) {
  assert(std::abs(glm::dot(normal, normal) - 1) < 1e-3f && "diffuse_transfer: normal not unit");
  // zh_clamped_cosine is the projection of max(cos, 0) itself (DC pi / sqrt(4 pi)), so
  // L . transfer is the irradiance integral L V max(n.w, 0) dw, without a 1 / pi (eq. 4.21).
  static const sh::Zonal<N> kCosine = sh::zh_clamped_cosine<N>();
  return sh::product<N>(visibility, sh::rotate_zh<N>(kCosine, normal));
}

template <int N>
sh::Coeffs<N> spherical_light_radiance(const glm::vec3& to_centre, float radius) {
  const float d = glm::length(to_centre);
  if (!(radius > 0) || !(d > radius) || !std::isfinite(d)) return sh::Coeffs<N>{};
  // Eq. 4.27: cap of half-angle asin(r / d) about +z, rotated towards the centre.
  return sh::rotate_zh<N>(sh::zh_cap<N>(std::asin(radius / d)), to_centre / d);
}

#define PENUMBRA_TRANSFER_INSTANTIATE(N)                                              \
  template sh::Coeffs<N> diffuse_transfer<N>(const sh::Coeffs<N>&, const glm::vec3&); \
  template sh::Coeffs<N> spherical_light_radiance<N>(const glm::vec3&, float);
PENUMBRA_TRANSFER_INSTANTIATE(2)
PENUMBRA_TRANSFER_INSTANTIATE(3)
PENUMBRA_TRANSFER_INSTANTIATE(4)
PENUMBRA_TRANSFER_INSTANTIATE(5)
PENUMBRA_TRANSFER_INSTANTIATE(6)
#undef PENUMBRA_TRANSFER_INSTANTIATE

}  // namespace penumbra::terrain_shadow
