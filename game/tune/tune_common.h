// What the tuner's system evaluators share (docs/tune.md): the options of a run, the error
// measure, a timer and the environment's SH.
//   rel_rms = sqrt(sum |E - E_ref|^2 / sum |E_ref|^2) over receivers, RGB together (the
//   accuracy tests' definition, tests/terrain_shadow/terrain_reference.h); a zero reference
//   gives +infinity unless the method is zero too.
// Threading: pure functions.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"

namespace penumbra::tune {

struct TuneOptions {
  int reference_samples = 1024;     // Monte Carlo directions per receiver (environment)
  int bounce_samples = 512;         // first-hit directions per probe test point (one bounce)
  int probe_capture_samples = 256;  // BakeSettings::samples of the probe bakes
  int key_lights = 1;   // sources of the sky shaded as key lights (sky_split.h; the demo's 1)
  int timing_reps = 3;  // timed runs per configuration (the minimum is kept)
  std::uint64_t seed = 1;
};

inline double rel_rms(std::span<const glm::vec3> method, std::span<const glm::vec3> reference) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < method.size() && i < reference.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(method[i][c]) - reference[i][c];
      num += d * d;
      den += static_cast<double>(reference[i][c]) * reference[i][c];
    }
  if (den == 0) return num == 0 ? 0 : std::numeric_limits<double>::infinity();
  return std::sqrt(num / den);
}

// Milliseconds of the fastest of `reps` runs of f().
template <class F>
double min_ms(int reps, F&& f) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  return best;
}

// The map's SH projection turned by `rotation` about +z (as the reference turns the map).
template <int N>
sh::CoeffsRgb<N> environment_sh(const data::EnvironmentMap& map, float rotation) {
  sh::CoeffsRgb<N> l = sh::project_equirect<N>(map.rgb.data(), map.width, map.height);
  for (auto& c : l) c = sh::rotate_z<N>(c, rotation);
  return l;
}

}  // namespace penumbra::tune
