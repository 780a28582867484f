// Dilation of invalid probes (probe_validity.h): inverse-squared-distance weights over the valid
// probes within a radius, found through a hash grid of that cell size.
#include "penumbra/systems/probe_bake/probe_validity.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace penumbra::probe_bake {
namespace {

std::uint64_t key(int x, int y, int z) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x) & 0x1FFFFF) << 42) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(y) & 0x1FFFFF) << 21) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(z) & 0x1FFFFF));
}

}  // namespace

std::size_t dilate(std::span<const glm::vec3> positions, std::span<ProbeState> state,
                   std::span<float> sh, std::size_t stride, float radius, int passes) {
  const std::size_t n = positions.size();
  auto invalid = [&](std::size_t i) {
    return state[i] != ProbeState::kValid && state[i] != ProbeState::kOffset &&
           state[i] != ProbeState::kDilated;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (invalid(i)) state[i] = ProbeState::kBlack;  // until filled
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  auto cell = [&](const glm::vec3& p, int k) {
    return static_cast<int>(std::floor(p[k] / radius));
  };
  for (std::size_t i = 0; i < n; ++i)
    grid[key(cell(positions[i], 0), cell(positions[i], 1), cell(positions[i], 2))].push_back(
        static_cast<std::uint32_t>(i));
  std::vector<double> acc(stride);
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<std::size_t> filled;
    std::vector<float> values;
    for (std::size_t i = 0; i < n; ++i) {
      if (state[i] != ProbeState::kBlack) continue;
      std::fill(acc.begin(), acc.end(), 0.0);
      double wsum = 0;
      const glm::vec3& p = positions[i];
      const int cx = cell(p, 0), cy = cell(p, 1), cz = cell(p, 2);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
            if (it == grid.end()) continue;
            for (std::uint32_t j : it->second) {
              if (state[j] == ProbeState::kBlack) continue;  // only valid / earlier-filled
              const glm::vec3 d = positions[j] - p;
              const double d2 = glm::dot(d, d);
              if (!(d2 <= double(radius) * radius) || d2 == 0) continue;
              const double w = 1.0 / d2;
              wsum += w;
              const float* s = sh.data() + j * stride;
              for (std::size_t k = 0; k < stride; ++k) acc[k] += w * s[k];
            }
          }
      if (wsum == 0) continue;
      filled.push_back(i);
      for (std::size_t k = 0; k < stride; ++k) values.push_back(static_cast<float>(acc[k] / wsum));
    }
    if (filled.empty()) break;
    // Written after the pass: a pass reads only what earlier passes settled (order-free).
    for (std::size_t f = 0; f < filled.size(); ++f) {
      state[filled[f]] = ProbeState::kDilated;
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(f * stride), stride,
                  sh.begin() + static_cast<std::ptrdiff_t>(filled[f] * stride));
    }
  }
  std::size_t black = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (state[i] == ProbeState::kBlack) {
      ++black;
      std::fill_n(sh.begin() + static_cast<std::ptrdiff_t>(i * stride), stride, 0.0f);
    }
  return black;
}

}  // namespace penumbra::probe_bake
