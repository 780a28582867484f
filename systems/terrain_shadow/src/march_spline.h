// Internal: the uniform cubic B-spline the horizon marches put through four consecutive angles,
// at a knot (1/6 2/3 1/6) and at the mid-point after it (1/48 23/48 23/48 1/48) ([Meier13]
// eq. 4.8-4.12, sec. 5.2); horizon_march.cpp and light_horizon_march.cpp.
#pragma once

namespace penumbra::terrain_shadow::detail {

inline float knot_value(float am, float a0, float a1) {
  return (am + 4 * a0 + a1) * (1.0f / 6);
}
inline float mid_value(float am, float a0, float a1, float a2) {
  return (am + 23 * (a0 + a1) + a2) * (1.0f / 48);
}

}  // namespace penumbra::terrain_shadow::detail
