// Fixture for tests/common/check_stability_table.py (not compiled): three calls, one of them in
// a parameterised test and one spanning several lines.
#include "common/stability.h"

TEST(Alpha, ZeroRadiusIsFinite) {
  PENUMBRA_STABILITY("a sphere of radius 0", "no shadow | finite", "radius clamped");
  const double err = 0.0125;
  PENUMBRA_STABILITY_MEASURE("max |E| error", err);
}

TEST_P(AlphaParam, NaNIsRejected) {
  PENUMBRA_STABILITY("a NaN height",
                     "std::invalid_argument naming the sample",
                     "-");
}
