// Probe validity (issue 14), the practice of Unity's adaptive probe volumes and DDGI: a probe
// whose rays hit back faces (it sits inside geometry) captures darkness, and objects near it turn
// black (godotengine/godot #77168). So
//  1. a probe whose back-face share is above `invalid_share` (Unity: 0.25) is invalid;
//  2. virtual offset: it leaves through the face its escape direction (the nearest back-face
//     hit) reaches, when that hit is within max_offset: along the face's outward normal to
//     clearance past the face's plane, clamped into the placed probes' bounding box (a probe off
//     a grid row or outside the grid's flat hull face makes sliver hull triangles that
//     extrapolate light across walls), and is captured again there; valid there -> kept;
//     both_sides: also the exit along the opposite direction (the other face of a thin wall),
//     when within max_offset; when both places are valid the probe becomes two, one on each
//     side (a one-sided offset puts a lit probe next to the dark side). Where tetrahedra still
//     cross a wall (no probe inside it, e.g. a 1.5 m grid in the room), edge rays
//     (probe_edge_rays.h, [Sukys14] sec. 3.2.2) add probes; docs/probe_bake.md "Edge rays";
//  3. dilation: a probe still invalid takes the inverse-squared-distance weighted mean of the
//     valid probes within dilation_radius; passes repeat with the filled probes as sources (each
//     pass reaches one radius further), up to dilation_passes;
//  4. a probe no pass reaches stays black (kBlack): the documented fallback for "all probes
//     invalid" (e.g. a volume wholly inside a solid) -- the cloud is still written and valid.
// No invalid probe ever keeps its own (inside-the-wall) capture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::probe_bake {

enum class ProbeState : std::uint8_t { kValid, kOffset, kDilated, kBlack };

struct ValiditySettings {
  float invalid_share = 0.25f;   // back-face share above which a probe is invalid (Unity)
  float max_offset = 0.5f;       // farthest virtual offset, in probe spacings
  float clearance = 0.1f;        // distance past the surface, in probe spacings
  float dilation_radius = 1.8f;  // in probe spacings: the 26 grid neighbours (sqrt 3 = 1.73)
  int dilation_passes = 4;
  bool both_sides = true;  // split an in-wall probe onto both faces (see 2.)
};

// Dilation (step 3, 4): sh holds `stride` floats per probe; the invalid probes' values (state
// not kValid / kOffset on entry) are overwritten; their state becomes kDilated or kBlack.
// Deterministic (fixed order, double sums). Returns the number left black.
std::size_t dilate(std::span<const glm::vec3> positions, std::span<ProbeState> state,
                   std::span<float> sh, std::size_t stride, float radius, int passes);

}  // namespace penumbra::probe_bake
