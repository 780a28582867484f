// SH logarithm and exponential, for accumulating visibility of many blockers as a sum of
// log-SH vectors followed by one exponential (Ren et al. 2006, as used in
// [Giraud] eq. 7-9 and [Guerrero08] eq. 6-7).
//
// Accuracy (tests/sh/exp_log_test.cpp, 4 bands, relative L2 error; blocker sums use
// log(eps) = -3 and sin(half-angle) 0.2-0.6):
//  - exp_ol against exp_numeric: 0.03% at |f^| = 0.1, 0.7% at 0.5, 2.5% at 1; use it only for
//    small zero-mean parts;
//  - exp_hyb against exp_numeric: 1.6% mean / 3.6% worst for one blocker, 6% / 12% for four,
//    12% / 24% for eight. The error comes from truncating each of the k squares to N bands,
//    not from the OL step (a smaller kHybOlNorm barely helps: measured 0.5 -> 0.01 changes the
//    8-blocker worst case from 0.25 to 0.22). Against the exact (projected) product visibility,
//    the whole log-sum + HYB pipeline is off by 14% mean / 20% worst for 1-4 blockers;
//  - many overlapping blockers (tens sharing a region, m log(eps) deep) break it: the squares
//    diverge. exp_visibility clamps the result to a vector some [0, 1]-valued function can
//    have, so it degrades to a bounded, finite visibility instead of blowing up;
//  - log_clamped projects log(max(f, eps)) with a quadrature: exact up to band truncation and
//    the clamp (values below eps become log(eps)).
#pragma once

#include "penumbra/sh/basis.h"

namespace penumbra::sh {

inline constexpr float kHybOlNorm = 0.125f;

// SH projection of log(max(f(w), eps)), by quadrature.
template <int N>
Coeffs<N> log_clamped(const Coeffs<N>& f, float eps);

// SH projection of exp(f(w)), by quadrature: the exponential OL and HYB approximate.
template <int N>
Coeffs<N> exp_numeric(const Coeffs<N>& f);

// Optimal linear exponential: exp(f) = e^{f_0 y_0} exp(f^), f^ = f without its DC term, and
// exp(f^) ~ a(|f^|) 1 + b(|f^|) f^ with a, b fitted by least squares, per norm, over
// blocker-like inputs (zero-mean parts of spherical-cap log-visibilities; exp_log.cpp).
template <int N>
Coeffs<N> exp_ol(const Coeffs<N>& f);

// Hybrid exponential: DC isolation, OL on f^ / 2^k, then k SH squares (HYB in Ren et al.).
template <int N>
Coeffs<N> exp_hyb(const Coeffs<N>& f, float ol_norm = kHybOlNorm);

// exp_hyb for visibility: the result is then clamped so it stays a vector some function with
// values in [0, 1] can have: 0 <= v_0 <= sqrt(4 pi) and |v|^2 <= sqrt(4 pi) v_0 (since
// integral v^2 <= integral v for 0 <= v <= 1). Graceful fallback for inputs beyond HYB's range.
template <int N>
Coeffs<N> exp_visibility(const Coeffs<N>& log_visibility);

// The fitted OL coefficients for a zero-mean part of norm `norm` (for tests and docs).
struct OlFit {
  float a, b;
};
template <int N>
OlFit ol_fit(float norm);

}  // namespace penumbra::sh
