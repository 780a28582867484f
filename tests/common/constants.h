// Constants the unit tests of several suites share, defined once (the test executables compile
// in unity batches, tests/CMakeLists.txt, where two file-local definitions would clash). In
// namespace penumbra, so that every suite's namespace finds them unqualified.
#pragma once

#include <numbers>

namespace penumbra {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kSqrt4Pi = 3.5449077f;  // sqrt(4 pi): Y_00 = 1 / kSqrt4Pi

}  // namespace penumbra
