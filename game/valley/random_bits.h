// Internal to the valley game: random bits from integers, the same on every platform (no
// <random> distributions, whose results the standard leaves to the library).
// Threading: pure functions.
#pragma once

#include <cstdint>

namespace penumbra::game::detail {

// A 32-bit hash step (xorshift-multiply, "lowbias32").
inline std::uint32_t mix_bits(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// The top 24 bits as a float in [0, 1).
inline float unit_float(std::uint32_t bits) {
  return static_cast<float>(bits >> 8) / 16777216.0f;
}

}  // namespace penumbra::game::detail
