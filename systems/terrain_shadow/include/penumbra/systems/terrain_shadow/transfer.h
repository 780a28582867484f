// Diffuse transfer and shading ([Meier13] eq. 4.20-4.21, 4.27-4.29).
// [Interface fixed by the system.]
//
// transfer = V * C(n): the SH product of the visibility with the clamped cosine about the unit
// normal n (sh::zh_clamped_cosine rotated to n). Irradiance E = L . transfer, with L the
// incident radiance in SH; the outgoing diffuse radiance is albedo / pi * E. Both products are
// truncated to N bands: E is exact for the band-limited L, V and C (e.g. constant L, V = 1:
// E = pi L).
// Threading: pure functions.
#pragma once

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::terrain_shadow {

// `normal` must be unit length (asserted in checked builds, not renormalised).
template <int N>
sh::Coeffs<N> diffuse_transfer(const sh::Coeffs<N>& visibility, const glm::vec3& normal);

// Incident radiance of a spherical light of unit radiance (scale the result by each channel's
// radiance), centre at `to_centre` (vector from the receiver, not normalised) and `radius`: the
// ZH of its cap of half-angle asin(radius / |to_centre|) ([Meier13] eq. 4.27, appendix A.1) rotated
// towards the centre. A receiver inside or on the light (|to_centre| <= radius), a light of
// radius <= 0 or a non-finite input gets zero (documented: the light is culled, like the
// reference integrator does).
template <int N>
sh::Coeffs<N> spherical_light_radiance(const glm::vec3& to_centre, float radius);

}  // namespace penumbra::terrain_shadow
