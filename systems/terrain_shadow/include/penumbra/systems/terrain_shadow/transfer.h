// Diffuse transfer and shading ([Meier13] eq. 4.20-4.21, 4.27-4.29).
// [Interface fixed by the system.]
//
// transfer = V * C(n): the SH product of the visibility with the clamped cosine about the unit
// normal n (sh::zh_clamped_cosine rotated to n). Irradiance E = L . transfer, with L the
// incident radiance in SH; the outgoing diffuse radiance is albedo / pi * E. Both products are
// truncated to N bands: E is exact for the band-limited L, V and C (e.g. constant L, V = 1:
// E = pi L).
//
// exact_diffuse_transfer (ours; the environment's default, TransferMethod::kExact): the exact
// projection proj_N(V max(0, n.w)) instead of the truncated product of the truncated V and C.
// The product above drops every coupling with bands of V and C at or above N (docs/
// terrain_shadow.md, "SH bands": at 4 bands that alone took the error from 2.8-5.1% to 3.5-7.0%).
// With the horizons raised to the tangent plane (raise_to_tangent_plane) max(0, n.w) is n.w on
// the visible set, a band-1 function, so proj_N(V (n.w)) needs V at N + 1 bands and nothing else:
// out_i = sum_j (n . G_ij) V_j, G_ij = integral y_i y_j w dw (sparse: bands l +- 1).
// Threading: pure functions; AzimuthFrame is immutable after construction.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::terrain_shadow {

// `normal` must be unit length (asserted in checked builds, not renormalised).
template <int N>
sh::Coeffs<N> diffuse_transfer(const sh::Coeffs<N>& visibility, const glm::vec3& normal);

// proj_N(V (n.w)) for V given at N + 1 bands (exact; with raise_to_tangent_plane's horizons it is
// proj_N(V max(0, n.w))). `normal` unit length (asserted in checked builds). N = 2..6.
template <int N>
sh::Coeffs<N> exact_diffuse_transfer(const sh::Coeffs<N + 1>& visibility, const glm::vec3& normal);
// The same for eight texels at once (one per vector lane; results equal to eight calls of
// exact_diffuse_transfer): visibility[8], normals[8], out[8].
template <int N>
void exact_diffuse_transfer_8(const sh::Coeffs<N + 1>* visibility, const glm::vec3* normals,
                              sh::Coeffs<N>* out);
// Its non-zero coupling components (G_ij)_c (one multiply-add each per call, plus 3 N^2 to weigh
// them by the normal): an operation count for benchmarks.
template <int N>
int exact_transfer_term_count();

// The azimuths phi_k = 2 pi k / n_phi of a horizon set (horizon.h) and the tangent plane on them.
class AzimuthFrame {
 public:
  explicit AzimuthFrame(int azimuths);
  int azimuths() const { return static_cast<int>(cos_.size()); }
  // out[k] = max(angles[k], elevation of the tangent plane of `normal` along phi_k): the
  // visible set above these horizons is where V = 1 and n.w >= 0 (up to the linear horizon
  // across each wedge, eq. 4.15). `out` may alias `angles`; no allocation.
  void raise_to_tangent_plane(const float* angles, const glm::vec3& normal, float* out) const;

 private:
  std::vector<float> cos_, sin_;
};

// Incident radiance of a spherical light of unit radiance (scale the result by each channel's
// radiance), centre at `to_centre` (vector from the receiver, not normalised) and `radius`: the
// ZH of its cap of half-angle asin(radius / |to_centre|) ([Meier13] eq. 4.27, appendix A.1) rotated
// towards the centre. A receiver inside or on the light (|to_centre| <= radius), a light of
// radius <= 0 or a non-finite input gets zero (documented: the light is culled, like the
// reference integrator does).
template <int N>
sh::Coeffs<N> spherical_light_radiance(const glm::vec3& to_centre, float radius);

}  // namespace penumbra::terrain_shadow
