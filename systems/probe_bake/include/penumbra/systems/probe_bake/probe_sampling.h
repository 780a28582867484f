// Sampling a probe's irradiance SH in 26 directions ([Sukys14] sec. 3.1.3, "Light probe
// sampling"): the 6 axes (+-x, +-y, +-z), the 12 sums of two non-collinear axes (the cube's
// edge midpoints, (+-1, +-1, 0) and permutations, normalized) and the 8 sums of three (the
// cube's corners, (+-1, +-1, +-1) / sqrt 3). The thesis uses the 6 axes for spawn-and-merge
// first, then all 26 for the gradient; both methods here use the 26.
// The contrast of two probes (sec. 3.1.3, "Contrast of spherical harmonics"): the largest
// Michelson contrast |a - b| / (a + b + floor) of their luminance over the 26 directions -- the
// sampled contrast, bounded in [0, 1], not the thesis's rejected coefficient MSE (unbounded, no
// threshold fits). `floor` keeps noise in near-black probes from reading as contrast.
// The irradiance vector ("gradient", sec. 3.1.2, after Chajdas et al.): sum over the 26
// directions of direction x luminance, divided by the sum of luminance; length in [0, 1]
// (0: isotropic light; towards 1: light from one side), pointing towards the brighter side.
#pragma once

#include <array>
#include <span>

#include <glm/vec3.hpp>

namespace penumbra::probe_bake {

inline constexpr int kSampleDirections = 26;
using DirectionSamples = std::array<float, kSampleDirections>;  // luminance per direction

// The 26 unit directions: axes [0, 6), edges [6, 18), corners [18, 26).
const std::array<glm::vec3, kSampleDirections>& sample_directions();

// Luminance (Rec. 709 weights) of the irradiance SH `sh` (3 * bands^2 floats, RGB, the
// cloud's layout: E(n) = sum_i e_i y_i(n)) in the 26 directions; negative ringing clamped to 0.
DirectionSamples sample_irradiance(std::span<const float> sh, int bands);

float probe_contrast(const DirectionSamples& a, const DirectionSamples& b, float floor);

// The irradiance vector (above); 0 for a black probe.
glm::vec3 irradiance_vector(const DirectionSamples& s);

}  // namespace penumbra::probe_bake
