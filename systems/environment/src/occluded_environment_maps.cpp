#include "penumbra/systems/environment/occluded_environment_maps.h"

#include <chrono>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "penumbra/sh/projection.h"
#include "penumbra/systems/environment/environment_prefilter.h"

namespace penumbra::environment {

namespace {

constexpr int kBands = sh::kDefaultBands;
static_assert(kBands >= 3, "the 3-band sets are the first 9 coefficients of the default ones");

using Sums = std::array<std::array<double, kBands * kBands>, 3>;

}  // namespace

OccludedEnvironmentMaps build_occluded_environment_maps(const data::EnvironmentMap& map,
                                                        const LightSourceDetection& detection) {
  const auto t0 = std::chrono::steady_clock::now();
  check_environment_map(map);
  const std::string name = map.source.empty() ? std::string("environment map") : map.source;
  if (detection.width != map.width || detection.height != map.height) {
    throw std::invalid_argument(name + ": detection of a " + std::to_string(detection.width) + "x" +
                                std::to_string(detection.height) + " map used with a " +
                                std::to_string(map.width) + "x" + std::to_string(map.height) +
                                " map");
  }
  const int n = static_cast<int>(detection.sources.size());
  if (n > kMaxSources) {
    throw std::invalid_argument(name + ": " + std::to_string(n) + " sources, more than " +
                                std::to_string(kMaxSources));
  }
  const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
  const auto w = static_cast<std::size_t>(map.width);

  // [Ambrosj16] Algorithm 1: BlackenPixelsInImage for every source, then sec. 4.2's projection.
  std::vector<float> black = map.rgb;
  std::vector<char> seen(texels, 0);
  std::vector<Sums> per_source(static_cast<std::size_t>(n));
  float y[kBands * kBands];
  for (int j = 0; j < n; ++j) {
    Sums& s = per_source[static_cast<std::size_t>(j)];
    for (auto& c : s) c.fill(0.0);
    for (std::uint32_t t : detection.sources[static_cast<std::size_t>(j)].texels) {
      if (t >= texels || seen[t]) {
        throw std::invalid_argument(name + ": source " + std::to_string(j) + " texel " +
                                    std::to_string(t) +
                                    (t >= texels ? " is outside the map" : " is in two sources"));
      }
      seen[t] = 1;
      const auto row = static_cast<int>(t / w);
      const double omega = sh::equirect_texel_solid_angle(row, map.width, map.height);
      const glm::vec3 dir =
          sh::equirect_direction((static_cast<float>(t % w) + 0.5f) / static_cast<float>(map.width),
                                 (static_cast<float>(row) + 0.5f) / static_cast<float>(map.height));
      sh::eval_basis<kBands>(dir, y);
      for (int c = 0; c < 3; ++c) {
        const double v = omega * map.rgb[3 * t + static_cast<std::size_t>(c)];
        for (int i = 0; i < kBands * kBands; ++i) s[static_cast<std::size_t>(c)][i] += v * y[i];
        black[3 * t + static_cast<std::size_t>(c)] = 0.0f;
      }
    }
  }
  const sh::CoeffsRgb<kBands> base =
      sh::project_equirect<kBands>(black.data(), map.width, map.height);

  OccludedEnvironmentMaps out;
  out.source_count = n;
  const std::size_t sets = std::size_t{1} << n;
  out.sh.resize(sets);
  out.sh3.resize(sets);
  for (std::size_t mask = 0; mask < sets; ++mask) {
    for (int c = 0; c < 3; ++c) {
      const auto cc = static_cast<std::size_t>(c);
      for (int i = 0; i < kBands * kBands; ++i) {
        double v = base[cc][static_cast<std::size_t>(i)];
        for (int j = 0; j < n; ++j)
          if (mask & (std::size_t{1} << j)) v += per_source[static_cast<std::size_t>(j)][cc][i];
        out.sh[mask][cc][static_cast<std::size_t>(i)] = static_cast<float>(v);
        if (i < 9) out.sh3[mask][cc][static_cast<std::size_t>(i)] = static_cast<float>(v);
      }
    }
  }
  out.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

std::array<glm::mat4, 3> irradiance_matrices(const sh::CoeffsRgb<3>& radiance) {
  // [Ambrosj16] eq. 3.15 constants. Penumbra's index l(l+1)+m: 0 L00, 1 L1-1 (y), 2 L10 (z),
  // 3 L11 (x), 4 L2-2 (xy), 5 L2-1 (yz), 6 L20, 7 L21 (xz), 8 L22 (x^2 - y^2).
  constexpr float c1 = 0.429043f, c2 = 0.511664f, c3 = 0.743125f, c4 = 0.886227f, c5 = 0.247708f;
  std::array<glm::mat4, 3> out;
  for (int c = 0; c < 3; ++c) {
    const auto& L = radiance[static_cast<std::size_t>(c)];
    glm::mat4 m(0.0f);  // glm is column-major: m[col][row]; M is symmetric
    m[0][0] = c1 * L[8];
    m[1][0] = m[0][1] = c1 * L[4];
    m[2][0] = m[0][2] = c1 * L[7];
    m[3][0] = m[0][3] = c2 * L[3];
    m[1][1] = -c1 * L[8];
    m[2][1] = m[1][2] = c1 * L[5];
    m[3][1] = m[1][3] = c2 * L[1];
    m[2][2] = c3 * L[6];
    m[3][2] = m[2][3] = c2 * L[2];
    m[3][3] = c4 * L[0] - c5 * L[6];
    out[static_cast<std::size_t>(c)] = m;
  }
  return out;
}

}  // namespace penumbra::environment
