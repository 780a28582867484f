// One sphere blocker seen from one receiver: the analytic log-SH of its visibility ([Giraud]
// eq. 24-26), after the receiver-plane rule that keeps receivers on or inside spheres from
// popping ([Guerrero08] sec. 6.2, after [Ren06]).
//
// Plane rule (ours; the documents give the idea, not the formula). For a receiver p with unit
// normal n and a sphere (c, r), let t = n.(c - p) + r be how far the sphere reaches above p's
// tangent plane:
//  - t <= 0: the sphere is wholly below the plane: culled;
//  - otherwise it is replaced by the sphere spanning the part above the plane, radius
//    r' = min(r, t / 2), centre c + (r - r') n (same top point; it touches the plane when it was
//    cut), and its log-visibility is scaled by w = smoothstep(t / 2r): 1 for a sphere wholly
//    above the plane, falling smoothly to 0 as the sphere sinks below it.
// A receiver inside a sphere is therefore never inside its replacement; a sphere resting on the
// receiver's plane (a boulder on the ground) keeps full weight and blocks up to the whole
// hemisphere towards it; the sphere a mesh vertex sits just inside (its own, mostly below its
// tangent plane) fades out. Everything is continuous in p, n, c and r.
//
// The cap's half-angle is asin(min(r'/d, 1)) with d = |c' - p| (guarded, [Giraud] eq. 24).
// Blockers whose sin(half-angle) is below `min_sin` are skipped, faded in over [min_sin,
// 2 min_sin] so the cut-off does not pop either. Ratio attenuation ([Giraud] sec. 4.2) scales
// the log-SH by r'/d.
//
// Threading: pure functions.
#pragma once

#include <cmath>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::blocker_accumulation {

// [Giraud] sec. 4.2: scale each blocker's log-SH by r / |c - p| (tames many overlapping blockers
// at the price of under-shadowing small near blockers in line with big far ones).
enum class RatioAttenuation { kOff, kOn };

// Which log-SH stands for one blocker's visibility.
//  - kCapEpsilon ([Giraud] eq. 26): log(eps) inside the cap, 0 outside (add_log_visibility).
//  - kClippedEigen ([Ren06]): the SH log of the cap's band-limited visibility, its product
//    matrix's eigenvalues clipped at eigen_clip of the largest (clipped_log_cap.h).
enum class BlockerLog { kCapEpsilon, kClippedEigen };

struct SphereBlockerSettings {
  float epsilon = 0.2f;  // visibility inside a blocker's cap before the log ([Giraud] fig. 7)
  RatioAttenuation ratio = RatioAttenuation::kOff;
  float min_sin = 0.05f;  // skip blockers smaller than this (sin of the angular radius)
  // Deepest log-visibility, in blockers (units of log eps), handed to the exponential: where
  // overlapping caps sum deeper, the whole sum is scaled back to this depth
  // (blocker_accumulation.h).
  float max_depth = 3.0f;
  BlockerLog log = BlockerLog::kCapEpsilon;
  float eigen_clip = 0.02f;  // kClippedEigen: the smallest eigenvalue kept, relative ([Ren06])
  bool operator==(const SphereBlockerSettings&) const = default;
};

// A sphere as one receiver sees it after the plane rule.
struct BlockerView {
  glm::vec3 axis{0.0f, 0.0f, 1.0f};  // unit, from the receiver towards the (replaced) centre
  float sin_angle = 0;               // sin of the cap's half-angle, in [0, 1]
  float weight = 0;                  // 0: culled or negligible
};

BlockerView view_blocker(const glm::vec3& p, const glm::vec3& n, const glm::vec3& centre,
                         float radius, const SphereBlockerSettings& s);

// Adds weight * log(eps) * cap(axis, angle) to `log_visibility` ([Giraud] eq. 26, rotated by
// the ZH rotation): coefficient (l, m) gains log(eps) w 2 pi / (2l + 1) (P_{l-1}(x) - P_{l+1}(x))
// y_lm(axis), x = cos(angle), P_{-1} = 1.
template <int N>
void add_log_visibility(const BlockerView& v, float log_eps, sh::Coeffs<N>& log_visibility);

}  // namespace penumbra::blocker_accumulation
