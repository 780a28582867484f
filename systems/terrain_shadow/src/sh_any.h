// Internal: real SH of any band count in double, in the library's convention (sh/basis.h: no
// Condon-Shortley phase, band 1 ordered (y, z, x), y_1^-1 = +sqrt(3 / 4 pi) y), for the tables
// that need one band more than sh::eval_basis instantiates (sh::kMaxBands = 6): the exact
// transfer's 7-band wedge table at 6 bands and its coupling coefficients. No trigonometry:
// y_lm = K_lm P_l^m(z) / sin^m * Re / Im (x + i y)^m.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

namespace penumbra::terrain_shadow::detail {

// out[l (l + 1) + m] = y_l^m(x, y, z) for l < bands; (x, y, z) unit.
inline void eval_basis_any(int bands, double x, double y, double z, double* out) {
  double re = 1, im = 0;  // (x + i y)^m
  double pmm = 1;         // (2m - 1)!!: P_m^m / sin^m
  for (int m = 0; m < bands; ++m) {
    if (m > 0) {
      pmm *= 2 * m - 1;
      const double r = re * x - im * y;
      im = re * y + im * x;
      re = r;
    }
    double pa = pmm, pb = 0;
    double k = 1;  // (l - m)! / (l + m)! for l = m: 1 / (2m)!
    for (int i = 2; i <= 2 * m; ++i) k /= i;
    for (int l = m; l < bands; ++l) {
      double p = pa;
      if (l == m + 1) {
        pb = z * (2 * m + 1) * pa;
        p = pb;
      } else if (l > m + 1) {
        p = ((2 * l - 1) * z * pb - (l + m - 1) * pa) / (l - m);
        pa = pb;
        pb = p;
      }
      if (l > m) k *= static_cast<double>(l - m) / (l + m);
      const double norm = std::sqrt((2 * l + 1) / (4 * std::numbers::pi) * k);
      if (m == 0) {
        out[l * (l + 1)] = norm * p;
      } else {
        out[l * (l + 1) + m] = std::sqrt(2.0) * norm * p * re;
        out[l * (l + 1) - m] = std::sqrt(2.0) * norm * p * im;
      }
    }
  }
}

}  // namespace penumbra::terrain_shadow::detail
