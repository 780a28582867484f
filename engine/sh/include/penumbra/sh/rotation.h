// Rotating SH functions. All rotations act on the function: the result represents
// g(w) = f(R^T w), i.e. f carried along by R (a lobe at direction d ends up at R d).
#pragma once

#include <array>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/zh.h"

namespace penumbra::sh {

// A zonal function (about +z) re-aligned to the unit direction `axis`:
// f_lm = sqrt(4 pi / (2l + 1)) z_l y_lm(axis) (Funk-Hecke; [Giraud] eq. 5).
template <int N>
Coeffs<N> rotate_zh(const Zonal<N>& z, const glm::vec3& axis);

// Rotation by `angle` radians about +z: per band, a 2x2 rotation of each (m, -m) pair.
template <int N>
Coeffs<N> rotate_z(const Coeffs<N>& f, float angle);

// General rotation, built once from a 3x3 rotation matrix (columns = images of x, y, z) and
// applied to many vectors. Per-band matrices from the Ivanic-Ruedenberg recurrence (J. Phys.
// Chem. 1996, 100(15); corrections 1998), seeded with band 1, which in the (y, z, x) order is
// the rotation matrix with permuted rows and columns.
template <int N>
class Rotation {
 public:
  explicit Rotation(const glm::mat3& r);
  Coeffs<N> apply(const Coeffs<N>& f) const;
  // Entry (m, n) of band l's (2l+1)x(2l+1) matrix, m, n in [-l, l].
  float band(int l, int m, int n) const;

 private:
  // Band l's matrix starts at offset_[l], row-major, (2l+1)^2 entries.
  std::array<int, N> offset_{};
  std::vector<float> m_;
};

}  // namespace penumbra::sh
