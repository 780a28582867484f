// [Ren06]'s log of a sphere blocker's visibility, the alternative to [Giraud]'s log(eps) cap
// (sphere_blocker.h): the SH logarithm of the cap's band-limited visibility itself.
//
// For a cap of sin(half-angle) s about +z, v = 1 outside the cone and 0 inside, projected to N
// bands. Its SH product matrix M_v (M_ij = integral v y_i y_j, the N-band truncated product by v)
// is symmetric; log M_v = U diag(log lambda) U^T with every eigenvalue lambda clipped to at least
// `clip` times the largest (a visibility is 0 on the blocked part, so M_v is near singular
// there and its log unbounded), and the log vector is log M_v applied to the constant 1
// (sqrt(4 pi) e_0): the SH of a function g is M_g (sqrt(4 pi) e_0), and M_{log v} ~ log M_v
// ([Ren06] sec. 4). The result is zonal; it is tabulated over cos(half-angle) and interpolated
// linearly, then rotated to the sphere's direction like the eps cap.
//
// Unlike the eps cap its depth is not a parameter: the clip and the cap's size set it (`depth`:
// the value at the axis of a blocked hemisphere). The depth limit of blocker_accumulation.h
// stays max_depth log(epsilon) either way.
// Measured against the eps cap: docs/blocker_accumulation.md.
// Threading: build once (about a millisecond per entry), then read from any number of threads.
#pragma once

#include <vector>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"

namespace penumbra::blocker_accumulation {

template <int N>
class ClippedLogCap {
 public:
  // Throws std::invalid_argument unless 0 < clip < 1 and entries >= 2.
  explicit ClippedLogCap(float clip = 0.02f, int entries = 257);

  float clip() const { return clip_; }
  // The log-ZH of the cap of sin(half-angle) `sin_angle` (clamped to [0, 1]) about +z.
  sh::Zonal<N> log_zh(float sin_angle) const;
  // The log-visibility at the axis of the widest cap (s = 1, a blocked hemisphere): negative.
  float depth() const { return depth_; }

  // Exact (untabulated) value at `sin_angle`, for tests.
  static sh::Zonal<N> compute(float sin_angle, float clip);

 private:
  float clip_;
  float depth_;
  std::vector<sh::Zonal<N>> table_;  // entries over s = 0 .. 1
};

// Adds v.weight * log_zh(v.sin_angle), rotated to v.axis, to `log_visibility`.
template <int N>
void add_log_visibility(const BlockerView& v, const ClippedLogCap<N>& cap,
                        sh::Coeffs<N>& log_visibility);

}  // namespace penumbra::blocker_accumulation
