// Random vectors drawn in one fixed order. In glm::vec3(d(rng), d(rng), d(rng)) the order of
// the draws is the compiler's: GCC evaluates a call's arguments, and an overloaded operator's
// operands, right to left; clang left to right. The same seed then gave clang other points, and
// bounds and tables set on GCC's points failed there (docs/ci.md, "Compilers"). These draw in
// GCC's order, z then y then x, so that every number set on GCC's build stays as it was.
#pragma once

namespace penumbra::test {

template <class Vec, class Rng, class DX, class DY, class DZ>
Vec draw_zyx(Rng& rng, DX& dx, DY& dy, DZ& dz) {
  const auto z = dz(rng);
  const auto y = dy(rng);
  const auto x = dx(rng);
  return Vec(x, y, z);
}

// The same distribution for all three.
template <class Vec, class Rng, class D>
Vec draw_zyx(Rng& rng, D& d) {
  return draw_zyx<Vec>(rng, d, d, d);
}

}  // namespace penumbra::test
