// Constants shared by the spherical light tests, defined once so that a unity build (the test
// targets' default, tests/CMakeLists.txt) sees one definition.
#pragma once

#include <numbers>

namespace penumbra::spherical_lights {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kSqrt4Pi = 3.5449077f;  // sqrt(4 pi): Y_00 = 1 / kSqrt4Pi

}  // namespace penumbra::spherical_lights
