// What a receiver needs of one spherical light (SL) it sees unblocked: the SL's average radiance
// towards the receiver ([Guerrero08] sec. 6.1, eq. 16-18) and the cosine-weighted solid angle of
// its cap (the average visibility of eq. 14 with nothing in between).
//
// AverageRadianceTable: eq. 16 weights the SL's radiance L_S(w_S) over its sphere by
// max(0, cos gamma), gamma the angle at the surface point between its normal w_S and the
// direction to the receiver. With the receiver at unit distance and sin(theta) = r / d, for a
// surface point at angle alpha from the centre-to-receiver direction,
//   cos gamma = (cos alpha - sin theta) / sqrt(1 - 2 sin theta cos alpha + sin^2 theta),
// which is eq. 17 simplified (sin(atan(a / b) - alpha) with a = 1 - sin theta cos alpha,
// b = sin theta sin alpha). Normalised to unit integral and projected on the zonal harmonics
// (midpoint rule, 2,048 points of cos alpha over [sin theta, 1], where it is > 0), tabulated at 256
// values of sin theta in [0, 1) and interpolated linearly. Eq. 18: L~ = w'_theta . L^c, w' the ZH
// turned to the direction from the SL's centre to the receiver in the SL's own frame (the object's
// inverse rotation, sec. 7.1).
//
// AverageRadianceWeight::kSolidAngle (ours): eq. 16 weights each surface point by cos gamma
// alone, but a surface point's share of what the receiver sees is the solid angle it subtends,
// cos gamma dA / |v|^2, |v| its distance to the receiver; the two agree for distant SLs and
// differ near them, where the side facing the receiver counts for more.
// docs/spherical_light_accuracy.md measures both.
//
// cap_cosine_integral: int over the cap of max(0, n.w) dw, exact, the cap clipped by the
// receiver's horizon (the sphere form factor times pi; Snyder's closed form as in Lagarde and de
// Rousiers, "Moving Frostbite to PBR", SIGGRAPH 2014 course, eq. 20).
//
// Threading: the table is immutable after construction; the functions are pure.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/lanes.h"
#include "penumbra/sh/zh.h"

namespace penumbra::spherical_lights {

enum class AverageRadianceWeight { kCosine, kSolidAngle };

template <int N>
class AverageRadianceTable {
 public:
  static constexpr int kEntries = 256;
  explicit AverageRadianceTable(AverageRadianceWeight weight = AverageRadianceWeight::kCosine);
  AverageRadianceWeight weight() const { return weight_; }
  // w_theta for an SL of sin(angular radius) `sin_angle` (clamped to [0, 1)).
  sh::Zonal<N> weights(float sin_angle) const;
  // Eq. 18: the average radiance of an SL with radiance SH `radiance` (its frame) towards a
  // receiver in unit direction `to_receiver` (its frame, from the centre), per channel.
  glm::vec3 average_radiance(const sh::CoeffsRgb<N>& radiance, float sin_angle,
                             const glm::vec3& to_receiver) const;

 private:
  AverageRadianceWeight weight_;
  std::vector<sh::Zonal<N>> table_;  // kEntries + 1 rows, sin theta = i / kEntries
};

// int_cap max(0, n.w) dw for a cap of half-angle asin(sin_angle) whose axis makes cosine
// `cos_beta` with the unit normal n (exact; pi sin^2 cos_beta when the cap is wholly above the
// horizon, 0 when wholly below).
float cap_cosine_integral(float sin_angle, float cos_beta);

// The same for 8 caps at once (sh::Lanes; the gather's per-receiver lanes), its arctangents by
// Cephes' atanf polynomial: within 5e-6 of the scalar form relative to max(value, 0.05) (test).
sh::Lanes cap_cosine_integral_lanes(sh::Lanes sin_angle, sh::Lanes cos_beta);

}  // namespace penumbra::spherical_lights
