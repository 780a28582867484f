#include "penumbra/systems/probe_cloud/exact_predicates.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include "common/random_draws.h"
#include "common/stability.h"

namespace penumbra::probe_cloud {
namespace {

using V = glm::dvec3;

int sign(double v) {
  return (v > 0) - (v < 0);
}

// Independent exact references on integer coordinates (|x| < 2^20): __int128 determinants.
__extension__ typedef __int128 I;
int orient_ref(const V& a, const V& b, const V& c, const V& d) {
  const I m[3][3] = {{I(b.x - a.x), I(b.y - a.y), I(b.z - a.z)},
                     {I(c.x - a.x), I(c.y - a.y), I(c.z - a.z)},
                     {I(d.x - a.x), I(d.y - a.y), I(d.z - a.z)}};
  const I det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return (det > 0) - (det < 0);
}

int insphere_ref(const V& a, const V& b, const V& c, const V& d, const V& e) {
  const V* p[4] = {&a, &b, &c, &d};
  I m[4][4];
  for (int i = 0; i < 4; ++i) {
    const I x = I(p[i]->x - e.x), y = I(p[i]->y - e.y), z = I(p[i]->z - e.z);
    m[i][0] = x;
    m[i][1] = y;
    m[i][2] = z;
    m[i][3] = x * x + y * y + z * z;
  }
  auto det3 = [&](int r0, int r1, int r2) {
    return m[r0][0] * (m[r1][1] * m[r2][3] - m[r1][3] * m[r2][1]) -
           m[r0][1] * (m[r1][0] * m[r2][3] - m[r1][3] * m[r2][0]) +
           m[r0][3] * (m[r1][0] * m[r2][1] - m[r1][1] * m[r2][0]);
  };
  // Laplace along column 2 (z) of the 4x4 [x y z lift].
  const I det = m[0][2] * det3(1, 2, 3) - m[1][2] * det3(0, 2, 3) + m[2][2] * det3(0, 1, 3) -
                m[3][2] * det3(0, 1, 2);
  // Our convention: > 0 inside for a positively oriented tetrahedron = -Shewchuk's det.
  return -((det > 0) - (det < 0));
}

const V a0(0, 0, 0), b0(1, 0, 0), c0(0, 1, 0), d0(0, 0, 1);

TEST(ExactPredicates, SignConventions) {
  EXPECT_GT(orient3d(a0, b0, c0, d0), 0);  // det[b-a, c-a, d-a] = 1
  EXPECT_LT(orient3d(b0, a0, c0, d0), 0);
  EXPECT_EQ(orient3d(a0, b0, c0, V(0.3, 0.4, 0)), 0);
  EXPECT_GT(insphere(a0, b0, c0, d0, V(0.25, 0.25, 0.25)), 0);
  EXPECT_LT(insphere(a0, b0, c0, d0, V(2, 2, 2)), 0);
  EXPECT_EQ(insphere(a0, b0, c0, d0, V(1, 1, 1)), 0);  // the unit cube's corners are cospherical
  EXPECT_LT(insphere(b0, a0, c0, d0, V(0.25, 0.25, 0.25)), 0);
}

TEST(ExactPredicates, NearDegenerateAtLargeOffsets) {
  PENUMBRA_STABILITY("near-coplanar / near-cospherical points at offsets up to 1e6",
                     "exact signs, exact zeros", "adaptive exact arithmetic ([Shewchuk97])");
  for (double offset : {0.0, 1.0, 1e6, 1e6 + 0.125, 3e7}) {
    const V o(offset, -offset, offset * 0.5);
    for (int e = 20; e <= 60; e += 8) {
      const double t = std::ldexp(1.0, -e);
      // Tiny perturbations of a coplanar / cospherical point, where representable at the offset.
      const V on_plane = o + V(0.5, 0.5, 0), up = on_plane + V(0, 0, t),
              down = on_plane - V(0, 0, t);
      if (up.z != on_plane.z && down.z != on_plane.z) {
        EXPECT_EQ(sign(orient3d(o + a0, o + b0, o + c0, up)), 1) << offset << " " << e;
        EXPECT_EQ(sign(orient3d(o + a0, o + b0, o + c0, down)), -1) << offset << " " << e;
      }
      const V on = o + V(1, 1, 1), in = on - V(0, 0, t), out = on + V(0, 0, t);
      if (in.z != on.z && out.z != on.z) {
        EXPECT_EQ(sign(insphere(o + a0, o + b0, o + c0, o + d0, in)), 1) << offset << " " << e;
        EXPECT_EQ(sign(insphere(o + a0, o + b0, o + c0, o + d0, out)), -1) << offset << " " << e;
      }
    }
    EXPECT_EQ(orient3d(o + a0, o + b0, o + c0, o + V(0.5, 0.5, 0)), 0);
    EXPECT_EQ(insphere(o + a0, o + b0, o + c0, o + d0, o + V(1, 1, 1)), 0);
  }
}

TEST(ExactPredicates, AgreesWithIntegerReference) {
  std::mt19937_64 rng(7);
  // Small integer boxes make zeros frequent; large coordinates make the filter fail often.
  for (int scale : {3, 1 << 18}) {
    std::uniform_int_distribution<int> coord(-scale, scale);
    auto pt = [&] { return penumbra::test::draw_zyx<V>(rng, coord); };
    int zeros = 0;
    for (int i = 0; i < 20000; ++i) {
      const V a = pt(), b = pt(), c = pt(), d = pt(), e = pt();
      const int o = orient_ref(a, b, c, d);
      ASSERT_EQ(sign(orient3d(a, b, c, d)), o);
      ASSERT_EQ(orient3d_sign(a, b, c, d), o);
      ASSERT_EQ(sign(insphere(a, b, c, d, e)), insphere_ref(a, b, c, d, e));
      zeros += o == 0;
    }
    if (scale == 3) {
      EXPECT_GT(zeros, 100);
    }
  }
  // Nearly coplanar and nearly cospherical integer sets: a lattice cube plus one unit off.
  const V big(1 << 19, 1 << 19, 1 << 19);  // dz = -1, 0, 1 around the plane
  for (int dz = -1; dz <= 1; ++dz) {
    const V q = big + V(3 << 10, 5 << 10, dz);
    EXPECT_EQ(sign(orient3d(big, big + V(1 << 12, 0, 0), big + V(0, 1 << 12, 0), q)),
              orient_ref(big, big + V(1 << 12, 0, 0), big + V(0, 1 << 12, 0), q));
  }
}

TEST(ExactPredicates, InexactDifferencesUseTheExpansionPath) {
  // Coordinates whose differences round: 1e6 + tiny, and widely different exponents.
  const V o(1e6, 1e6, 1e6);
  const double tiny = std::ldexp(1.0, -30);
  const V a = o, b = o + V(1, tiny, 0), c = o + V(tiny, 1, 0);
  const V d = V(0.5, 0.5, 0) + o;  // coplanar with a, b, c only up to tiny terms
  // Reference by hand: the plane through a, b, c; exact with long double on these values.
  const long double ref =
      ((long double)(b.x - a.x) * (c.y - a.y) - (long double)(b.y - a.y) * (c.x - a.x)) *
      ((long double)d.z - a.z);
  EXPECT_EQ(sign(orient3d(a, b, c, d)), sign(double(ref)));
  // Points on the plane z = x whose differences round (0.1 - 1e-30): exactly coplanar, and
  // one ulp off it on either side.
  const V p0(0.1, 1e-30, 0.1), p1(1e-30, 0.7, 1e-30), p2(0.3, 0.2, 0.3), p3(5e-31, 1e-20, 5e-31);
  reset_exact_fallback_count();
  EXPECT_EQ(orient3d(p0, p1, p2, p3), 0);
  const int side = orient3d_sign(p0, p1, p2, V(p3.x, p3.y, 1.0));  // the side z > x
  ASSERT_NE(side, 0);
  EXPECT_EQ(orient3d_sign(p0, p1, p2, V(p3.x, p3.y, std::nextafter(p3.z, 1.0))), side);
  EXPECT_EQ(orient3d_sign(p0, p1, p2, V(p3.x, p3.y, std::nextafter(p3.z, -1.0))), -side);
  EXPECT_GE(exact_fallback_count(), 1u);
}

TEST(ExactPredicates, MixedMagnitudesAreConsistentUnderSymmetries) {
  // Near-degenerate sets with coordinates of wildly different exponents (differences round, so
  // the full expansion path runs): the exact sign must flip under an odd permutation, survive an
  // even one, and survive scaling by a power of two.
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<int> pick(0, 5);
  const double mags[6] = {0.0, 1e-30, 3e-9, 1.0, 1e6 + 0.125, 7e11};
  auto coord = [&] { return (rng() & 1 ? 1 : -1) * mags[pick(rng)] * (1 + (rng() % 8) * 0x1p-50); };
  reset_exact_fallback_count();
  for (int i = 0; i < 3000; ++i) {
    V p[5];
    for (V& q : p) q = V(coord(), coord(), coord());
    if (i % 2) p[4] = p[0] + (p[1] - p[0]) * 0.5;  // nearly on an edge: nearly degenerate
    const int o = sign(orient3d(p[0], p[1], p[2], p[3]));
    ASSERT_EQ(sign(orient3d(p[1], p[0], p[2], p[3])), -o);
    ASSERT_EQ(sign(orient3d(p[1], p[2], p[0], p[3])), o);
    ASSERT_EQ(sign(orient3d(p[0] * 0x1p-40, p[1] * 0x1p-40, p[2] * 0x1p-40, p[3] * 0x1p-40)), o);
    const int s = sign(insphere(p[0], p[1], p[2], p[3], p[4]));
    ASSERT_EQ(sign(insphere(p[1], p[0], p[2], p[3], p[4])), -s);
    ASSERT_EQ(sign(insphere(p[2], p[3], p[0], p[1], p[4])), s);
    ASSERT_EQ(sign(insphere(p[0] * 0x1p-20, p[1] * 0x1p-20, p[2] * 0x1p-20, p[3] * 0x1p-20,
                            p[4] * 0x1p-20)),
              s);
    // The 4x4 determinant is symmetric in all five points up to sign: e swapped with a.
    ASSERT_EQ(sign(insphere(p[4], p[1], p[2], p[3], p[0])), -s);
  }
  EXPECT_GT(exact_fallback_count(), 100u);
}

TEST(ExactPredicates, PerturbationBreaksCosphericalTiesConsistently) {
  // All 8 corners of a cube are cospherical. For any tetrahedron of them and a fifth corner,
  // the perturbed sign is never 0, does not depend on how the tetrahedron is written (an even
  // permutation with its ids), and the point with the largest id is "outside".
  std::vector<V> corner;
  for (int i = 0; i < 8; ++i) corner.push_back(V(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  int decided = 0;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      for (int c = 0; c < 8; ++c)
        for (int d = 0; d < 8; ++d) {
          if (orient3d_sign(corner[a], corner[b], corner[c], corner[d]) <= 0) continue;
          for (int e = 0; e < 8; ++e) {
            if (e == a || e == b || e == c || e == d) continue;
            const int s = insphere_perturbed(corner[a], corner[b], corner[c], corner[d], corner[e],
                                             a, b, c, d, e);
            ASSERT_NE(s, 0);
            // An even permutation of the tetrahedron (with its ids) keeps the answer.
            EXPECT_EQ(s, insphere_perturbed(corner[b], corner[c], corner[a], corner[d], corner[e],
                                            b, c, a, d, e));
            if (e == 7) {
              EXPECT_EQ(s, -1);  // the query has the largest id: lifted most, so outside
            }
            ++decided;
          }
        }
  EXPECT_GT(decided, 100);
  // Strict answers are not perturbed.
  EXPECT_EQ(insphere_perturbed(a0, b0, c0, d0, V(0.25, 0.25, 0.25), 9, 8, 7, 6, 5), 1);
  EXPECT_EQ(insphere_perturbed(a0, b0, c0, d0, V(5, 5, 5), 0, 1, 2, 3, 4), -1);
}

TEST(ExactPredicates, PerturbationMatchesAnExplicitTinyLifting) {
  // Perturbing the lifting of point i by eps^(i-ish) means: for a cospherical e with a smaller
  // id than every tetrahedron vertex, the vertex with the largest id decides. Compare with a
  // real (non-symbolic) tiny move of that vertex outward: e ends inside the new sphere exactly
  // when the perturbed answer says "inside".
  const V a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1), e(1, 1, 1);
  ASSERT_EQ(insphere(a, b, c, d, e), 0);
  // d has the largest id: raising d's lift is like moving d slightly outward along its radius.
  const int s = insphere_perturbed(a, b, c, d, e, 1, 2, 3, 4, 0);
  const V centre(0.5, 0.5, 0.5);
  const V moved = d + (d - centre) * 1e-6;
  EXPECT_EQ(s, sign(insphere(a, b, c, moved, e)));
}

}  // namespace
}  // namespace penumbra::probe_cloud
