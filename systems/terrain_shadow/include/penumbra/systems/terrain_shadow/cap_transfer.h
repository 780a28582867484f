// Cap-vs-horizon shading of one spherical light (TerrainShadowConfig::light_shading =
// kCapHorizon; ours, not the thesis's SH path of [Meier13] eq. 4.22-4.29). The light matters
// only inside its cap, so the visibility is modelled only there: the horizon towards the light
// (radial_horizon_sweep.h, or light_horizon_march.h, or ray_horizon), then cap_transfer, the
// cosine-weighted solid angle of the part of the cap above that horizon and above the
// receiver's tangent plane, int_cap V(w) max(0, n.w) dw, integrated directly (no SH, so no
// ringing and no band-limit blur of small lights): E = L * cap_transfer.
// Where its time goes: docs/terrain_shadow.md ("Light shading, measured") and
// docs/terrain_shadow_log.md ("Lights, third round").
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
// (n.c), exact; horizon above the whole cap: 0; one horizon sample (a constant horizon) and the
// cap above the tangent plane: the lens between the cap's circle and the horizon's, exact in
// closed form (two arcs' boundary integrals, no strips; the light's common case). Caps that
// contain the zenith take every chord at its centre's azimuth (near receivers under a light,
// which the horizon rarely reaches).
//
// Threading: pure functions.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace penumbra::terrain_shadow {

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
// quadrature with a constant horizon (light_shading_test.cpp), in units of pi rho^2: caps in
// front of the tangent plane (closed form) within 3.5e-4, the quadrature's own accuracy; any
// cap (up to 70 degrees, around the zenith, cut by the tangent plane) within 3e-2 with 8
// strips, 1.6e-3 with 64.
inline constexpr int kMaxCapStrips = 64;
float cap_transfer(const LightCap& cap, const glm::vec3& normal, const float* horizon, int count,
                   int strips = 8);

// Eight receivers at once (struct of arrays): lane l has to_centre (dx, dy, dz)[l], unit normal
// (nx, ny, nz)[l] and `count` horizon samples horizon[k][l] (radians) at
// cap_horizon_direction(cap, k, count). Where bit l of the result is clear, e[l] is what
// make_light_cap and cap_transfer give (to float rounding, within 2e-5 pi rho^2: tested): 0 for
// a receiver inside the light, behind its tangent plane (n.d <= -radius) or under a horizon
// above the whole cap, pi rho^2 (n.c) for a cap wholly above the horizon and the tangent plane,
// else its lens (count 1, in front of the tangent plane) or its chords (all lanes at once, one
// chord a step). Bit l set: a cap with rho >= `wide` (the caller may take more horizon samples
// for it and pass it again with `wide` infinite), and with `defer_chords` every lane that
// needs chords (they cost the same for one lane as for eight, so a caller gathers them and
// passes them again). AVX2 where the build has it; per lane through cap_transfer otherwise
// (deferring every lit lane).
struct CapLanes {
  float dx[8], dy[8], dz[8], nx[8], ny[8], nz[8];
  float horizon[kMaxCapHorizons][8];
  int count = 1;  // horizon samples per lane, 1..kMaxCapHorizons
};
unsigned cap_transfer8(const CapLanes& in, float radius, float wide, int strips, bool defer_chords,
                       float* e);

// A light's first pass over its receivers, sixteen at once: cap_transfer8 with one horizon
// sample and defer_chords on lanes 0-7 and 8-15, the same floats and the same bits set (tested
// bit for bit). One AVX-512 kernel where the CPU has it (sweep_lanes.h's sweep_isa(); on the
// 512-bit lanes its chain of square roots, divisions and polynomials serves sixteen receivers
// in the time eight took), else two cap_transfer8 calls.
struct CapLanes16 {
  float dx[16], dy[16], dz[16], nx[16], ny[16], nz[16];
  float horizon[16];
};
unsigned cap_first_pass16(const CapLanes16& in, float radius, float wide, float* e);

// A light's second pass over the receivers whose caps its tangent plane cuts (|n.d| < radius),
// sixteen at once: cap_transfer8 with `wide` infinite and no deferral on lanes 0-7 and 8-15,
// the same floats (tested bit for bit; no lane is handed back). One AVX-512 kernel where the
// CPU has it (the cut caps' chords are a light's costliest lanes; sixteen serve in about the
// time eight took); a batch with a lane in front of the tangent plane that the horizon cuts
// with several samples (front chords, rare in this pass), and CPUs without AVX-512, run two
// cap_transfer8 calls.
struct CapChordLanes16 {
  float dx[16], dy[16], dz[16], nx[16], ny[16], nz[16];
  float horizon[kMaxCapHorizons][16];
  int count = 1;  // horizon samples per lane, 1..kMaxCapHorizons
};
void cap_chords16(const CapChordLanes16& in, float radius, int strips, float* e);

}  // namespace penumbra::terrain_shadow
