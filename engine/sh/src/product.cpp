#include "penumbra/sh/product.h"

#include <iterator>

#include "../generated/product_generated.h"

namespace penumbra::sh {
namespace g = generated;

template <int N>
Coeffs<N> product(const Coeffs<N>& f, const Coeffs<N>& h) {
  Coeffs<N> out;
  if constexpr (N == 2) g::product_2(f.data(), h.data(), out.data());
  if constexpr (N == 3) g::product_3(f.data(), h.data(), out.data());
  if constexpr (N == 4) g::product_4(f.data(), h.data(), out.data());
  if constexpr (N == 5) g::product_5(f.data(), h.data(), out.data());
  if constexpr (N == 6) g::product_6(f.data(), h.data(), out.data());
  return out;
}

template <int N>
Coeffs<N> square(const Coeffs<N>& f) {
  Coeffs<N> out;
  if constexpr (N == 2) g::square_2(f.data(), out.data());
  if constexpr (N == 3) g::square_3(f.data(), out.data());
  if constexpr (N == 4) g::square_4(f.data(), out.data());
  if constexpr (N == 5) g::square_5(f.data(), out.data());
  if constexpr (N == 6) g::square_6(f.data(), out.data());
  return out;
}

namespace {
template <int N>
const g::GauntEntry* gaunt_begin() {
  if constexpr (N == 2) return std::begin(g::kGaunt2);
  if constexpr (N == 3) return std::begin(g::kGaunt3);
  if constexpr (N == 4) return std::begin(g::kGaunt4);
  if constexpr (N == 5) return std::begin(g::kGaunt5);
  if constexpr (N == 6) return std::begin(g::kGaunt6);
}
template <int N>
const g::GauntEntry* gaunt_end() {
  if constexpr (N == 2) return std::end(g::kGaunt2);
  if constexpr (N == 3) return std::end(g::kGaunt3);
  if constexpr (N == 4) return std::end(g::kGaunt4);
  if constexpr (N == 5) return std::end(g::kGaunt5);
  if constexpr (N == 6) return std::end(g::kGaunt6);
}
}  // namespace

template <int N>
Coeffs<N> product_sparse(const Coeffs<N>& f, const Coeffs<N>& h) {
  Coeffs<N> out{};
  for (const g::GauntEntry* e = gaunt_begin<N>(); e != gaunt_end<N>(); ++e) {
    out[e->i] += e->value * f[e->j] * h[e->k];
  }
  return out;
}

template <int N>
int gaunt_entry_count() {
  return static_cast<int>(gaunt_end<N>() - gaunt_begin<N>());
}

template <int N>
int factored_term_count() {
  int n = 0;
  for (const g::GauntEntry* e = gaunt_begin<N>(); e != gaunt_end<N>(); ++e) n += e->j <= e->k;
  return n;
}

#define PENUMBRA_PRODUCT_INSTANTIATE(N)                                         \
  template Coeffs<N> product<N>(const Coeffs<N>&, const Coeffs<N>&);           \
  template Coeffs<N> square<N>(const Coeffs<N>&);                              \
  template Coeffs<N> product_sparse<N>(const Coeffs<N>&, const Coeffs<N>&);    \
  template int gaunt_entry_count<N>();                                         \
  template int factored_term_count<N>();
PENUMBRA_PRODUCT_INSTANTIATE(2)
PENUMBRA_PRODUCT_INSTANTIATE(3)
PENUMBRA_PRODUCT_INSTANTIATE(4)
PENUMBRA_PRODUCT_INSTANTIATE(5)
PENUMBRA_PRODUCT_INSTANTIATE(6)
#undef PENUMBRA_PRODUCT_INSTANTIATE

}  // namespace penumbra::sh
