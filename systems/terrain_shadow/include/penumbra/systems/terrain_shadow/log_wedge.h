// Log-SH visibility of a height field from its horizon angles ([Giraud]
// sec. 4.1, eq. 15-23), so that terrain visibility can be summed with blockers' log-visibility
// and exponentiated once (sh/exp_log.h). [Interface fixed by the system.]
//
// Each azimuth's slice is the NLP projection of log(eps) below the horizon and 0 above
// (eq. 15-16, sh::nlp_log_slice); a wedge interpolates its two border slices linearly in
// azimuth (eq. 19), which integrates to the (N*N) x (2N) operator M_lin applied to the two
// border vectors (eq. 20-23; 16 x 8 for N = 4). The canonical wedge is rotated about z to phi_k
// and the wedges are summed. Outside every wedge the log-visibility is 0 (visible).
// Threading: immutable after construction.
#pragma once

#include <vector>

#include "penumbra/sh/basis.h"

namespace penumbra::terrain_shadow {

template <int N>
class LogWedge {
 public:
  // Throws std::invalid_argument for azimuths < 3 or log_eps >= 0 or non-finite.
  LogWedge(int azimuths, float log_eps);

  int azimuths() const { return azimuths_; }
  float log_eps() const { return log_eps_; }
  // M_lin, row-major (N*N rows, 2N columns), eq. 21.
  const std::vector<float>& m_lin() const { return m_lin_; }

  // Log-SH visibility from a point's n_phi horizon angles (horizon.h layout; elevations in
  // [-pi/2, pi/2], clamped to it, NaN read as -pi/2): sum_k rotate_z(M_lin [v_k; v_k+1], phi_k)
  // with v_k = sh::nlp_log_slice<N>(angles[k], log_eps), to float precision (2e-7 relative).
  // No allocation; about 250 ns for N = 4 and 32 azimuths on one core.
  sh::Coeffs<N> log_visibility(const float* angles) const;

 private:
  int azimuths_;
  float log_eps_;
  std::vector<float> m_lin_;
  static constexpr int kLanes = 8;
  static constexpr int kColumn = (N * N + kLanes - 1) / kLanes * kLanes;  // padded column
  // Per azimuth k, the (N*N) x N matrix R(phi_k) M_L + R(phi_{k-1}) M_R (column-major, columns
  // of kColumn floats, slice normalisation folded in) that takes slice k's Legendre integrals
  // to its share of both wedges it borders (log_wedge.cpp).
  std::vector<float> gather_;
};

}  // namespace penumbra::terrain_shadow
