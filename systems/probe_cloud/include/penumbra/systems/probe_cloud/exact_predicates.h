// Exact geometric predicates on double coordinates ([Shewchuk97]): a floating-point filter with
// a dynamic error bound, then an exact evaluation by expansion arithmetic (two-sum, two-product
// with fma, expansion sums and scaling). The SIGN of every result is exact for any finite
// inputs whose products (up to fifth powers of coordinate differences, and their rounding
// errors) neither overflow nor underflow: true for coordinates that came from floats unless two
// points lie closer than about 1e-30 (the build merges such duplicates first). The magnitude is
// only an approximation of the determinant.
// Threading: pure functions; the exact fallback uses a per-thread scratch buffer, so any number
// of threads may call them at once.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

namespace penumbra::probe_cloud {

// det[b-a, c-a, d-a]: > 0 when (a, b, c, d) is a positively oriented tetrahedron, i.e. d lies
// on the side of the plane abc that (b-a) x (c-a) points to; 0 when the four are coplanar.
// (The opposite sign of Shewchuk's orient3d; this is the convention of data/probe_cloud.h.)
double orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

// For (a, b, c, d) with orient3d > 0: > 0 when e is strictly inside their circumsphere, < 0
// outside, 0 on it. The sign flips for a negatively oriented (a, b, c, d).
double insphere(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                const glm::dvec3& e);

// Sign (-1, 0, +1) of orient3d, exact.
int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                  const glm::dvec3& d);

// The sign of insphere with a symbolic perturbation that never returns 0 ([Devillers11]): every
// point is lifted by an infinitesimal that grows with its `id` (any total order, e.g. the point's
// index; ids must be distinct), so cospherical ties are broken consistently across all tetrahedra
// of a triangulation. Requires orient3d(a, b, c, d) > 0. Returns +1: e inside (conflict), -1:
// outside.
int insphere_perturbed(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                       const glm::dvec3& d, const glm::dvec3& e, std::uint32_t ia, std::uint32_t ib,
                       std::uint32_t ic, std::uint32_t id, std::uint32_t ie);

// How many predicate calls fell through the filter to the exact stage on this thread (tests,
// benchmarks). Not reset by anything but reset_exact_fallback_count().
std::uint64_t exact_fallback_count();
void reset_exact_fallback_count();

}  // namespace penumbra::probe_cloud
