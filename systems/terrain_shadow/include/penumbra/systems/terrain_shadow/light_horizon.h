// Cap-vs-horizon shading of one spherical light (TerrainShadowConfig::light_shading =
// kCapHorizon; ours, not the thesis's SH path of [Meier13] eq. 4.22-4.29).
//
// The light matters only inside its cap, so this models the visibility only there:
//  - RadialHorizonSweep (TerrainShadowConfig::cap_method kSweep, the default): the exact
//    horizon of every texel towards the light's foot, by line sweeps radiating from it, in
//    amortised O(1) per line sample (about 2 samples per texel).
//  - LightHorizonMarch (kMarch): the horizon along one direction (the light's azimuth, or a
//    few across the cap) by the thesis's pyramid march: horizon_march.h for one direction per
//    call ([Meier13] eq. 4.5-4.14, 4.22-4.25: sample distances, level choice eq. 4.14, elevation eq.
//    4.5-4.6 with the receiver at level 0, uniform cubic B-spline maximum over knots and
//    mid-points, 1/6 2/3 1/6 and 1/48 23/48 23/48 1/48, and the spline at the light's own
//    distance). For an azimuth 2 pi k / n_phi it gives what march_horizons gives (to 1e-6 rad,
//    light_shading_test.cpp). Scalar, O(log d) samples per call.
//  - cap_transfer: the cosine-weighted solid angle of the part of the cap above that horizon
//    and above the receiver's tangent plane, int_cap V(w) max(0, n.w) dw, integrated directly
//    (no SH, so no ringing and no band-limit blur of small lights): E = L * cap_transfer.
// Where its time goes: docs/terrain_shadow.md ("Light shading, measured").
//
// Integration: the cap projected orthographically onto the plane perpendicular to its centre
// direction c is a disc of radius rho = r / |d|; with w = c0 c + s s^ + u u^ (u^ "up", s^
// horizontal, c0 = sqrt(1 - s^2 - u^2)) the solid angle is ds du / c0. The disc is cut into
// `strips` chords of constant s at s = rho cos(psi_j), psi_j = (j + 1/2) pi / strips (the
// midpoint rule in psi, exact for the unoccluded disc). Along a chord the horizon (elevation >
// omega) bounds u by square roots alone (u = a cos e -+ sqrt(1 - s^2 - a^2) sin e, a = sin
// omega, e the centre's elevation), and the integral of (n.w) / c0 du is closed-form (an asin
// and a square root): eight chords at a time. A cap the tangent plane cuts is integrated in t,
// u = sqrt(1 - s^2) sin t (du / c0 = dt), where the plane bounds t by a sinusoid. The horizon
// is taken constant along a chord, at the azimuth of the chord's centre (u = 0), and linear in
// s between the horizon samples (sin of the angle interpolated; constant beyond the outer
// samples). Fast paths: horizon below the whole cap and cap above the tangent plane: pi rho^2
// (n.c), exact; horizon above the whole cap: 0. Caps that contain the zenith take every chord
// at its centre's azimuth (near receivers under a light, which the horizon rarely reaches).
//
// Threading: pure functions and classes whose const members may run concurrently.
#pragma once

#include <array>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/assets/height_field.h"
#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"

namespace penumbra::terrain_shadow {

// Horizons along arbitrary directions from a built pyramid (see the header comment).
class LightHorizonMarch {
 public:
  // The pyramid must stay alive and unchanged while this is used. Throws
  // std::invalid_argument for an unbuilt pyramid or a bad level offset.
  LightHorizonMarch(const HeightPyramid& pyramid, const MarchParams& march);

  // Elevation (radians, may be negative) of the horizon from texel (x, y) along the unit plane
  // direction `dir`, using terrain up to plane distance `limit` cells (the light's; eq. 4.24):
  // the samples up to the first one beyond `limit`, the spline's maximum up to `limit` (eq.
  // 4.25). No sample in range (limit < 1 cell, or the ray leaves the field at once): -pi/2.
  float horizon(int x, int y, glm::vec2 dir, float limit) const;

  int samples() const { return static_cast<int>(d_.size()); }

 private:
  const HeightPyramid* pyramid_;
  std::vector<float> d_;             // sample distances in cells (d_0 = 1, d_{i+1} = d_i + sr^i)
  std::vector<float> inv_metres_;    // 1 / (d_i * cell_size)
  std::vector<const float*> level_;  // level data read by sample i (eq. 4.14)
};

// Exact horizons of every texel towards one plane point, the light's foot F (the plane
// position of its centre), for terrain between the texel and F only ([Meier13] eq. 4.22 with the
// true terrain, no pyramid): a line sweep like horizon_sweep.h, with lines radiating from F
// instead of parallel. Each of the four sides of F (+x, -x, +y, -y; |slope| <= 1 about its
// major axis) has lines v = V0 + r m_j, r the major-axis distance from F, slopes m_j = j / J
// with J = ceil(the farthest column's r): lines at most a cell apart at the far border, denser
// towards F (about 2 samples per texel in all). Each line is sampled where it crosses the major
// axis's grid lines (heights interpolated linearly in that column: the exact terrain there)
// and swept outwards from F keeping the upper convex hull of the samples passed, so each
// sample's horizon towards F is the tangent to that hull: exact, amortised O(1) per sample. A
// texel's horizon interpolates (in angle) those of the two lines either side of it in its
// column, as the sweep does; a texel on a line gets exactly ray_horizon towards F (tests).
// With F outside the field, a texel beside which a line has left the field takes ray_horizon
// itself (its own ray may leave the field where the line does not).
// Memory: one float per line sample (about 2 to 4 x width x height). Threading: run() uses
// tbb::parallel_for in the caller's arena; horizon() is const and may run concurrently.
class RadialHorizonSweep {
 public:
  // `foot`: plane position (metres, relative to sample (0, 0)); any finite point, inside the
  // field or not. Inputs are not validated (validate_horizon_input). Keeps a reference to
  // `field` for horizon(). `reach` (metres): texels farther than that along the major axis of
  // their side are not swept (horizon() gives -pi/2 there); those within it get what a sweep
  // without a reach gives, bit for bit.
  // `regions` (texels, clipped to the field), when not empty: only texels in them are asked for
  // afterwards, so each line is swept only as far as the farthest of their texels it serves, and
  // lines serving none are not swept (horizon() elsewhere is unspecified); those texels get the
  // same horizons, bit for bit. A light re-shading a quarter of the tiles sweeps about that
  // share of the line samples (light_refresh.h).
  void run(const assets::HeightField& field, float height_scale, glm::vec2 foot,
           float reach = std::numeric_limits<float>::infinity(),
           std::span<const TexelRect> regions = {});
  // Elevation (radians) of the horizon of texel (x, y) towards the foot; -pi/2 when no terrain
  // lies in between (the foot within a column of the texel, or outside the field).
  float horizon(int x, int y) const;

 private:
  struct Side {
    bool x_major = true;
    int sign = 1;                  // direction of the major axis away from F
    int u_first = 0, columns = 0;  // first column (major coordinate) and count
    int j_lo = 0, lines = 0;       // line j_lo + l is stored at row l
    float lines_per_slope = 1;     // J
    std::vector<float> angle;      // lines x columns; NaN outside the field
    std::vector<int> line_end;     // with regions: columns swept per line (empty: all)
  };
  // Side::line_end from the regions (run()).
  void limit_lines(Side& side, std::span<const TexelRect> regions) const;
  std::array<Side, 4> sides_;
  const assets::HeightField* field_ = nullptr;
  float height_scale_ = 1;
  glm::vec2 foot_{0.0f};  // in cells
  bool foot_inside_ = true;
};

// A spherical light's cap seen from a receiver, in the frame cap_transfer integrates in.
struct LightCap {
  glm::vec3 dir{0.0f, 0.0f, 1.0f};  // unit, towards the centre (c)
  glm::vec2 plane_dir{1.0f, 0.0f};  // unit horizontal part of dir (any when straight up/down)
  float rho = 0;                    // sin of the half-angle: radius / distance, in (0, 1)
  float cos_half = 1;               // sqrt(1 - rho^2)
  float sin_e = 1, cos_e = 0;       // elevation of dir
  float plane_distance = 0;         // |to_centre.xy| (metres)
};

// False (the light contributes nothing) for radius <= 0, a receiver inside or on the light
// (|to_centre| <= radius) or a non-finite input.
bool make_light_cap(const glm::vec3& to_centre, float radius, LightCap& cap);

// Plane direction (unit) of horizon sample j of `count` (1 <= count <= kMaxCapHorizons): the
// azimuth of the cap's point s = rho tau_j, u = 0, tau_j = -cos(pi (j + 1) / (count + 1))
// (count 1: the centre's own azimuth).
inline constexpr int kMaxCapHorizons = 4;
glm::vec2 cap_horizon_direction(const LightCap& cap, int j, int count);

// int_cap V(w) max(0, n.w) dw (steradians; E = radiance * this), with V = 1 above the horizon
// given by `horizon[j]` (elevation, radians) at cap_horizon_direction(cap, j, count), `normal`
// unit. 1 <= count <= kMaxCapHorizons; strips is clamped to [1, kMaxCapStrips]. Against a fine
// quadrature with a constant horizon (light_shading_test.cpp), in units of pi rho^2: caps under
// 3.4 degrees away from the zenith within 2.8e-3 with 8 strips; any cap (up to 70 degrees,
// around the zenith, cut by the tangent plane) within 3e-2 with 8 strips, 1.7e-3 with 64.
inline constexpr int kMaxCapStrips = 64;
float cap_transfer(const LightCap& cap, const glm::vec3& normal, const float* horizon, int count,
                   int strips = 8);

}  // namespace penumbra::terrain_shadow
