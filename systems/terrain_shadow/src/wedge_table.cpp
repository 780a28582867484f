// Wedge tables: SH projections of one visibility wedge, tabulated over its two border angles,
// and the per-texel sum of rotated wedges ([Meier13] eq. 4.15-4.19, 4.26).
//
// Table layout: node (a, b) (w_left = node a, w_right = node b) is the N*N vector in 8-lane
// blocks from block a * row + b * B (B = ceil(N*N / 8), row = resolution * B + a cache line), so
// one bilinear lookup reads two runs of 2 B contiguous blocks.
// visibility() never forms a rotated wedge: with A_k = cos(m phi_k) and B_k = +-sin(m phi_k)
// per coefficient, rotate_z(w, phi_k)_i = A_k,i w_i + B_k,p(i) w_p(i), where p swaps (l, m) and
// (l, -m); it accumulates U = sum A_k w_k and T = sum B'_k w_k (B'_k,i = B_k,p(i)) elementwise
// and permutes T once per texel.
#include "penumbra/systems/terrain_shadow/wedge_table.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>

#include "penumbra/sh/projection.h"

#include "lanes.h"
#include "sh_any.h"
#include "sweep_lanes.h"
#include "wedge_sum.h"

namespace penumbra::terrain_shadow {
namespace {

// Quadrature orders of wedge_exact: the integrands are trigonometric polynomials of degree
// <= N + 1 in the elevation and analytic in phi; 16 points reach float precision (checked
// against 32 and against the closed-form cap in wedge_table_test.cpp).
constexpr int kElevationPoints = 16;
constexpr int kAzimuthPoints = 16;

struct Rule {
  std::vector<double> x, w;  // nodes and weights on [-1, 1]
};

// Gauss-Legendre nodes on [-1, 1], taken from sh::SphereQuadrature (its z nodes; the weights
// there include the azimuth range 2 pi).
Rule gauss_legendre(int n) {
  const sh::SphereQuadrature q = sh::SphereQuadrature::gauss(n, 1);
  Rule r;
  for (int i = 0; i < n; ++i) {
    r.x.push_back(q.directions[i].z);
    r.w.push_back(q.weights[i] / (2 * std::numbers::pi));
  }
  return r;
}

const Rule& elevation_rule() {
  static const Rule r = gauss_legendre(kElevationPoints);
  return r;
}
const Rule& azimuth_rule() {
  static const Rule r = gauss_legendre(kAzimuthPoints);
  return r;
}

// Adds to `acc` the projection of the visible part of azimuths [phi0, phi1] of the wedge,
// where the visible elevations are (max(w(phi), floor), pi/2]; w linear with w(0) = w_left,
// w(dphi) = w_right. The bound is smooth on [phi0, phi1] (callers split at the kink).
template <int N>
void integrate_piece(double phi0, double phi1, double w_left, double w_right, double dphi,
                     double floor, double* acc) {
  const Rule& ra = azimuth_rule();
  const Rule& re = elevation_rule();
  float y[N * N];
  for (std::size_t a = 0; a < ra.x.size(); ++a) {
    const double phi = phi0 + 0.5 * (phi1 - phi0) * (ra.x[a] + 1);
    const double wa = 0.5 * (phi1 - phi0) * ra.w[a];
    const double e0 = std::max(w_left + (phi / dphi) * (w_right - w_left), floor);
    const double half = 0.5 * (std::numbers::pi / 2 - e0);
    if (half <= 0) continue;
    const double cp = std::cos(phi), sp = std::sin(phi);
    for (std::size_t e = 0; e < re.x.size(); ++e) {
      const double elev = e0 + half * (re.x[e] + 1);
      const double ce = std::cos(elev);
      if constexpr (N <= sh::kMaxBands) {
        const glm::vec3 dir(static_cast<float>(cp * ce), static_cast<float>(sp * ce),
                            static_cast<float>(std::sin(elev)));
        sh::eval_basis<N>(dir, y);
      } else {  // one band above the library's (the exact transfer's table at 6 bands)
        double yd[N * N];
        detail::eval_basis_any(N, cp * ce, sp * ce, std::sin(elev), yd);
        for (int i = 0; i < N * N; ++i) y[i] = static_cast<float>(yd[i]);
      }
      const double weight = wa * half * re.w[e] * ce;  // d omega = cos(elev) d elev d phi
      for (int i = 0; i < N * N; ++i) acc[i] += weight * y[i];
    }
  }
}

double domain_min(WedgeDomain domain) {
  return domain == WedgeDomain::kHemisphere ? 0 : -std::numbers::pi / 2;
}

// Eight floats on vector lanes (GCC/Clang vector extension, as in sh/basis.cpp); a table node
// is blocks<N>() aligned 8-float blocks.
using detail::kLanes;
using detail::Lanes;
using detail::load;
using detail::store;

template <int N>
constexpr int blocks() {
  return (N * N + kLanes - 1) / kLanes;
}

template <class Block>
inline Lanes load_block(const Block& b) {
  static_assert(sizeof(Block) == sizeof(Lanes));
  Lanes v;
  std::memcpy(&v, b.f, sizeof v);
  return v;
}

// Table coordinate of an angle: lower node in [0, resolution - 2] and fraction in [0, 1],
// clamped to the table; NaN reads as the lowest node.
struct Lookup {
  std::size_t index;
  float frac;
};
struct Coords {
  using IntLanes = int __attribute__((vector_size(32)));
  float lo, inv_step, top;
  int last;
  Coords(float lowest, float inverse_step, int resolution)
      : lo(lowest),
        inv_step(inverse_step),
        top(static_cast<float>(resolution - 1)),
        last(resolution - 2) {}

  void one(float w, int* index, float* frac) const {
    float x = (w - lo) * inv_step;
    x = x > 0 ? x : 0;
    x = x < top ? x : top;
    const int i = std::min(static_cast<int>(x), last);
    *index = i;
    *frac = x - static_cast<float>(i);
  }
  void lanes(const float* w, int* index, float* frac) const {  // kLanes angles
    Lanes x = (load(w) - lo) * inv_step;
    x = x > 0 ? x : 0;
    x = x < top ? x : top;
    IntLanes i = __builtin_convertvector(x, IntLanes);
    i = i < last ? i : last;
    std::memcpy(index, &i, sizeof i);
    store(frac, x - __builtin_convertvector(i, Lanes));
  }
};
inline Lookup lookup(float w, float lo, float inv_step, int resolution) {
  Lookup out;
  int i;
  Coords(lo, inv_step, resolution).one(w, &i, &out.frac);
  out.index = static_cast<std::size_t>(i);
  return out;
}

// Swaps (l, m) and (l, -m).
template <int N>
constexpr std::array<int, N * N> partner() {
  std::array<int, N * N> p{};
  for (int l = 0; l < N; ++l) {
    for (int m = -l; m <= l; ++m) p[sh::index(l, m)] = sh::index(l, -m);
  }
  return p;
}

}  // namespace

template <int N>
sh::Coeffs<N> wedge_exact(float w_left, float w_right, float dphi, WedgeDomain domain) {
  if (!(dphi > 0 && dphi <= 2 * std::numbers::pi + 1e-6)) {
    throw std::invalid_argument("wedge_exact: dphi " + std::to_string(dphi) + " outside (0, 2 pi]");
  }
  const double floor = domain_min(domain);
  const double wl = std::clamp<double>(w_left, -std::numbers::pi / 2, std::numbers::pi / 2);
  const double wr = std::clamp<double>(w_right, -std::numbers::pi / 2, std::numbers::pi / 2);
  double acc[N * N] = {};
  // Eq. 4.18 / 4.26: visible above the linear horizon (and, on the hemisphere, above 0).
  // Split where w(phi) crosses the floor, so each piece has a smooth lower bound.
  if ((wl - floor) * (wr - floor) < 0) {
    const double t = (floor - wl) / (wr - wl);  // in (0, 1)
    integrate_piece<N>(0, t * dphi, wl, wr, dphi, floor, acc);
    integrate_piece<N>(t * dphi, dphi, wl, wr, dphi, floor, acc);
  } else {
    integrate_piece<N>(0, dphi, wl, wr, dphi, floor, acc);
  }
  sh::Coeffs<N> out;
  for (int i = 0; i < N * N; ++i) out[i] = static_cast<float>(acc[i]);
  return out;
}

template <int N>
WedgeTable<N>::WedgeTable(int azimuths, WedgeDomain domain, int resolution)
    : azimuths_(azimuths), resolution_(resolution), domain_(domain) {
  if (azimuths < 3) {
    throw std::invalid_argument("WedgeTable: " + std::to_string(azimuths) +
                                " azimuths (need >= 3)");
  }
  if (resolution < 2) {
    throw std::invalid_argument("WedgeTable: resolution " + std::to_string(resolution) +
                                " (need >= 2)");
  }
  constexpr int kB = blocks<N>();
  const double lo = domain_min(domain), step = (std::numbers::pi / 2 - lo) / (resolution - 1);
  lo_ = static_cast<float>(lo);
  inv_step_ = static_cast<float>(1 / step);
  const float dphi = static_cast<float>(2 * std::numbers::pi / azimuths);
  // Rows one cache line longer than their nodes: a power-of-two row stride would put a column's
  // nodes into one L1 set.
  row_ = static_cast<std::size_t>(resolution) * kB + 64 / sizeof(Block);
  table_.assign(static_cast<std::size_t>(resolution) * row_, Block{});
  for (int a = 0; a < resolution; ++a) {
    for (int b = 0; b < resolution; ++b) {
      const sh::Coeffs<N> w = wedge_exact<N>(static_cast<float>(lo + a * step),
                                             static_cast<float>(lo + b * step), dphi, domain);
      Block* node = &table_[a * row_ + b * kB];
      for (int i = 0; i < N * N; ++i) node[i / kLanes].f[i % kLanes] = w[i];
    }
  }
  // Per azimuth: A_k (cos m phi_k), then B'_k (see the file comment); padding stays 0.
  rotation_.assign(static_cast<std::size_t>(azimuths) * 2 * kB, Block{});
  for (int k = 0; k < azimuths; ++k) {
    Block* a = &rotation_[static_cast<std::size_t>(k) * 2 * kB];
    Block* b = a + kB;
    const double phi = 2 * std::numbers::pi * k / azimuths;
    for (int l = 0; l < N; ++l) {
      for (int m = -l; m <= l; ++m) {
        // rotate_z: out(l, m) = c f(l, m) - s f(l, -m); out(l, -m) = s f(l, m) + c f(l, -m).
        // B'_i multiplies w_i on its way to p(i): +s from m > 0 to -m, -s from -m to m.
        const double c = std::cos(std::abs(m) * phi), sn = std::sin(std::abs(m) * phi);
        const int i = sh::index(l, m);
        a[i / kLanes].f[i % kLanes] = static_cast<float>(c);
        b[i / kLanes].f[i % kLanes] = static_cast<float>(m > 0 ? sn : m < 0 ? -sn : 0.0);
      }
    }
  }
}

template <int N>
sh::Coeffs<N> WedgeTable<N>::wedge(float w_left, float w_right) const {
  constexpr int kB = blocks<N>();
  const Lookup l = lookup(w_left, lo_, inv_step_, resolution_);
  const Lookup r = lookup(w_right, lo_, inv_step_, resolution_);
  const Block* c00 = &table_[l.index * row_ + r.index * kB];
  const Block* c10 = c00 + row_;
  const float g00 = (1 - l.frac) * (1 - r.frac), g01 = (1 - l.frac) * r.frac;
  const float g10 = l.frac * (1 - r.frac), g11 = l.frac * r.frac;
  sh::Coeffs<N> out;
  for (int i = 0; i < N * N; ++i) {
    const int v = i / kLanes, e = i % kLanes;
    out[i] =
        g00 * c00[v].f[e] + g01 * c00[kB + v].f[e] + g10 * c10[v].f[e] + g11 * c10[kB + v].f[e];
  }
  return out;
}

template <int N>
sh::Coeffs<N> WedgeTable<N>::visibility(const float* angles) const {
  constexpr int kB = blocks<N>();
  static constexpr auto kPartner = partner<N>();
  static_assert(kB <= detail::kMaxWedgeBlocks);
  Lanes u[kB] = {}, t[kB] = {};
  float uf[kB * kLanes] = {}, tf[kB * kLanes] = {};  // the AVX-512 kernel's sums
#ifdef __AVX2__
  const bool avx512 = detail::sweep_isa() == detail::SweepIsa::kAvx512;
#else
  constexpr bool avx512 = false;
#endif
  const std::size_t row = row_;
  const Block* table = table_.data();
  const Block* rot = rotation_.data();
  // A chunk of angles at a time: table coordinates, then bilinear weights, on vector lanes;
  // the wedge loop then only loads, multiplies and adds (no conversion chains to hide).
  constexpr int kChunk = 64;
  int index[kChunk + 1];
  float frac[kChunk + 1], g00[kChunk], g01[kChunk], g10[kChunk], g11[kChunk];
  const Coords coords(lo_, inv_step_, resolution_);
  for (int k0 = 0; k0 < azimuths_; k0 += kChunk) {
    const int count = std::min(kChunk, azimuths_ - k0);
    int j = 0;
    for (; j + kLanes <= count; j += kLanes) coords.lanes(angles + k0 + j, index + j, frac + j);
    for (; j < count; ++j) coords.one(angles[k0 + j], index + j, frac + j);
    coords.one(angles[k0 + count < azimuths_ ? k0 + count : 0], index + count, frac + count);
    j = 0;
    for (; j + kLanes <= count; j += kLanes) {
      const Lanes fl = load(frac + j), fr = load(frac + j + 1);
      store(g00 + j, (1 - fl) * (1 - fr));
      store(g01 + j, (1 - fl) * fr);
      store(g10 + j, fl * (1 - fr));
      store(g11 + j, fl * fr);
    }
    for (; j < count; ++j) {
      const float fl = frac[j], fr = frac[j + 1];
      g00[j] = (1 - fl) * (1 - fr), g01[j] = (1 - fl) * fr;
      g10[j] = fl * (1 - fr), g11[j] = fl * fr;
    }
    if (avx512) {
      const detail::WedgeSumInput in{table[0].f, row, kB,  rot[0].f, index,
                                     g00,        g01, g10, g11,      count};
      detail::avx512::wedge_sum(in, uf, tf);
      rot += static_cast<std::size_t>(count) * 2 * kB;
      continue;
    }
    for (j = 0; j < count; ++j, rot += 2 * kB) {
      const Block* c00 = table + static_cast<std::size_t>(index[j]) * row +
                         static_cast<std::size_t>(index[j + 1]) * kB;
      const Block* c10 = c00 + row;
#pragma GCC unroll 8
      for (int v = 0; v < kB; ++v) {
        // One product and three multiply-adds in a chain (paired sums would take five).
        const Lanes w = ((g00[j] * load_block(c00[v]) + g01[j] * load_block(c00[kB + v])) +
                         g10[j] * load_block(c10[v])) +
                        g11[j] * load_block(c10[kB + v]);
        u[v] += load_block(rot[v]) * w;
        t[v] += load_block(rot[kB + v]) * w;
      }
    }
  }
  if (!avx512) {
    std::memcpy(uf, u, sizeof uf);
    std::memcpy(tf, t, sizeof tf);
  }
  sh::Coeffs<N> out;
  for (int i = 0; i < N * N; ++i) out[i] = uf[i] + tf[kPartner[i]];
  return out;
}

#define PENUMBRA_WEDGE_INSTANTIATE(N) \
  template class WedgeTable<N>;       \
  template sh::Coeffs<N> wedge_exact<N>(float, float, float, WedgeDomain);
PENUMBRA_WEDGE_INSTANTIATE(2)
PENUMBRA_WEDGE_INSTANTIATE(3)
PENUMBRA_WEDGE_INSTANTIATE(4)
PENUMBRA_WEDGE_INSTANTIATE(5)
PENUMBRA_WEDGE_INSTANTIATE(6)
PENUMBRA_WEDGE_INSTANTIATE(7)  // the exact transfer at 6 bands (transfer.h)
#undef PENUMBRA_WEDGE_INSTANTIATE

}  // namespace penumbra::terrain_shadow
