// SH visibility from horizon angles by wedge tables ([Meier13] eq. 4.15-4.19,
// 4.26; Snyder and Nowrouzezahrai 2008). [Interface fixed by the system.]
//
// Azimuth k spans the wedge [phi_k, phi_k + dphi], dphi = 2 pi / n_phi, over which the horizon
// is interpolated linearly between the two border angles (eq. 4.15). A table holds, for
// resolution x resolution pairs of border angles (w_l, w_r), the SH projection of the wedge's
// visibility (1 above the interpolated horizon, 0 below; eq. 4.17-4.18) in canonical position
// [0, dphi]; visibility() looks up each wedge of a texel, rotates it about z to phi_k and sums
// (eq. 4.19).
//  - kHemisphere (environment light): angles in [0, pi/2], directions below the horizontal
//    plane are invisible (eq. 4.18).
//  - kSphere (local lights): angles in [-pi/2, pi/2] over the whole sphere (eq. 4.26).
// Accuracy: entries are wedge_exact (quadrature error < 1e-7); between nodes the bilinear
// interpolation dominates: at most 1.5e-5 per wedge on the hemisphere, 6e-5 on the sphere
// (64 x 64, 32 azimuths, N = 4; wedge_table_test.cpp). Construction integrates resolution^2
// wedges (about 30 ms for 64 x 64, N = 4). visibility() costs about 100 ns per texel for N = 4
// and 32 azimuths on one core (x86-64-v3).
// Threading: immutable after construction; wedge() and visibility() may run concurrently.
#pragma once

#include <cstddef>
#include <vector>

#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/horizon.h"  // CacheLineAllocator

namespace penumbra::terrain_shadow {

enum class WedgeDomain { kHemisphere, kSphere };

template <int N>
class WedgeTable {
 public:
  // Throws std::invalid_argument for azimuths < 3 or resolution < 2.
  WedgeTable(int azimuths, WedgeDomain domain, int resolution = 64);

  int azimuths() const { return azimuths_; }
  int resolution() const { return resolution_; }
  WedgeDomain domain() const { return domain_; }

  // Canonical wedge [0, dphi] for border angles (w_l, w_r), interpolated bilinearly between
  // table entries; angles outside the domain's range are clamped to it (NaN reads as its
  // lowest angle: open sky).
  sh::Coeffs<N> wedge(float w_left, float w_right) const;

  // Eq. 4.19: total visibility from a texel's n_phi horizon angles (horizon.h layout): wedge k
  // spans [phi_k, phi_k+1] with borders angles[k], angles[(k + 1) % n_phi]. The hot loop of
  // the terrain shadow system; no allocation.
  sh::Coeffs<N> visibility(const float* angles) const;

 private:
  int azimuths_, resolution_;
  WedgeDomain domain_;
  float lo_ = 0, inv_step_ = 0;  // node a is at lo_ + a / inv_step_
  struct alignas(32) Block {     // one 8-lane vector: aligned loads never split a cache line
    float f[8];
  };
  // Node (a, b) is B = ceil(N*N / 8) blocks from block a * row_ + b * B, zero-padded.
  std::size_t row_ = 0;
  // On cache-line boundaries (with rows of whole lines): the AVX-512 loop loads two blocks at
  // once, and an even node's pair then never splits a line.
  std::vector<Block, CacheLineAllocator<Block>> table_;
  std::vector<Block, CacheLineAllocator<Block>> rotation_;  // per azimuth: B blocks cos(m phi_k),
                                                            // B blocks signed sin
};

// The same wedge integrated directly by quadrature (no table): for tests and table building.
// Visible above the linear horizon and, for kHemisphere, above 0 (the kink where the horizon
// crosses 0 is integrated exactly); angles are clamped to [-pi/2, pi/2]. Throws
// std::invalid_argument unless 0 < dphi <= 2 pi.
template <int N>
sh::Coeffs<N> wedge_exact(float w_left, float w_right, float dphi, WedgeDomain domain);

}  // namespace penumbra::terrain_shadow
