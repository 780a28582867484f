#include "penumbra/sh/projection.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra::sh {

SphereQuadrature SphereQuadrature::gauss(int n_z, int n_phi) {
  if (n_z < 1 || n_phi < 1) throw std::invalid_argument("SphereQuadrature::gauss: sizes must be positive");
  // Gauss-Legendre nodes on [-1, 1] by Newton iteration on P_n (double precision).
  std::vector<double> nodes, weights;
  for (int i = 1; i <= n_z; ++i) {
    double x = std::cos(std::numbers::pi * (i - 0.25) / (n_z + 0.5));
    double dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n_z; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n_z == 1) p0 = 1;  // P_0
      dp = n_z * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    nodes.push_back(x);
    weights.push_back(2 / ((1 - x * x) * dp * dp));
  }
  SphereQuadrature q;
  const double dphi = 2 * std::numbers::pi / n_phi;
  for (int i = 0; i < n_z; ++i) {
    const double z = nodes[i], r = std::sqrt(std::max(0.0, 1 - z * z));
    for (int a = 0; a < n_phi; ++a) {
      const double phi = dphi * (a + 0.5);
      q.directions.emplace_back(static_cast<float>(r * std::cos(phi)),
                                static_cast<float>(r * std::sin(phi)), static_cast<float>(z));
      q.weights.push_back(static_cast<float>(weights[i] * dphi));
    }
  }
  return q;
}

glm::vec3 equirect_direction(float u, float v) {
  const float phi = 2 * std::numbers::pi_v<float> * u;
  const float theta = std::numbers::pi_v<float> * v;
  const float s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

glm::vec2 equirect_uv(const glm::vec3& dir) {
  float phi = std::atan2(dir.y, dir.x);
  if (phi < 0) phi += 2 * std::numbers::pi_v<float>;
  const float theta = std::acos(std::fmax(-1.0f, std::fmin(1.0f, dir.z)));
  return {phi / (2 * std::numbers::pi_v<float>), theta / std::numbers::pi_v<float>};
}

float equirect_texel_solid_angle(int y, int width, int height) {
  const double t0 = std::numbers::pi * y / height, t1 = std::numbers::pi * (y + 1) / height;
  return static_cast<float>(2 * std::numbers::pi / width * (std::cos(t0) - std::cos(t1)));
}

template <int N>
CoeffsRgb<N> project_equirect(const float* rgb, int width, int height) {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("project_equirect: map size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is not positive");
  }
  CoeffsRgb<N> out{};
  float y[N * N];
  for (int row = 0; row < height; ++row) {
    const float w = equirect_texel_solid_angle(row, width, height);
    const float v = (row + 0.5f) / static_cast<float>(height);
    for (int col = 0; col < width; ++col) {
      const float* texel = rgb + 3 * (static_cast<std::size_t>(row) * width + col);
      eval_basis<N>(equirect_direction((col + 0.5f) / static_cast<float>(width), v), y);
      for (int c = 0; c < 3; ++c) {
        const float value = texel[c] * w;
        for (int i = 0; i < N * N; ++i) out[c][i] += value * y[i];
      }
    }
  }
  return out;
}

template CoeffsRgb<2> project_equirect<2>(const float*, int, int);
template CoeffsRgb<3> project_equirect<3>(const float*, int, int);
template CoeffsRgb<4> project_equirect<4>(const float*, int, int);
template CoeffsRgb<5> project_equirect<5>(const float*, int, int);
template CoeffsRgb<6> project_equirect<6>(const float*, int, int);

}  // namespace penumbra::sh
