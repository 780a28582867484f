// SH products: the projection of the pointwise product of two band-limited functions,
// truncated to N bands: (f * g)_i = sum_jk Gamma_ijk f_j g_k ([Giraud] eq. 6).
//
// product/square run generated straight-line code (scripts/gen_sh_code.py): each pair product
// f_j g_k + f_k g_j is formed once and feeds every output with a non-zero Gamma. The
// *_sparse variants walk the list of non-zero (i, j, k, Gamma) entries: the straightforward
// implementation, kept as the reference for tests and the benchmark baseline.
#pragma once

#include "penumbra/sh/basis.h"

namespace penumbra::sh {

template <int N>
Coeffs<N> product(const Coeffs<N>& f, const Coeffs<N>& g);

// product(f, f), about half the multiplications.
template <int N>
Coeffs<N> square(const Coeffs<N>& f);

template <int N>
Coeffs<N> product_sparse(const Coeffs<N>& f, const Coeffs<N>& g);

// Number of non-zero Gamma_ijk entries with i, j, k < N*N.
template <int N>
int gaunt_entry_count();
// Multiply-adds the factored product performs: one per non-zero Gamma_ijk with j <= k (plus the
// pair products themselves, about N^4 / 2 of them): its operation count, for benchmarks.
template <int N>
int factored_term_count();

}  // namespace penumbra::sh
