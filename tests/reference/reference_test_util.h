// Procedural inputs and exact values for the reference-integrator tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/reference/estimators.h"

namespace penumbra::reference::test {

constexpr double kPi = std::numbers::pi;

// The unit vector at polar angle theta from +z and azimuth phi from +x.
inline glm::vec3 unit(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Row y's edges in z = cos(theta): top (larger) and bottom.
inline double z_top(int y, int h) {
  return std::cos(kPi * y / h);
}
inline double z_bottom(int y, int h) {
  return std::cos(kPi * (y + 1) / h);
}

// A map whose texel (x, y) holds f(x, y, direction at the texel centre) in every channel
// scaled by `tint`.
inline data::EnvironmentMap make_map(int w, int h, const std::function<glm::vec3(int, int)>& f,
                                     std::string source = "procedural") {
  data::EnvironmentMap m;
  m.width = w;
  m.height = h;
  m.source = std::move(source);
  m.rgb.resize(3 * static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const glm::vec3 v = f(x, y);
      float* t = m.rgb.data() + 3 * (static_cast<std::size_t>(y) * w + x);
      t[0] = v.x, t[1] = v.y, t[2] = v.z;
    }
  }
  return m;
}

inline data::EnvironmentMap constant_map(int w, int h, glm::vec3 radiance) {
  return make_map(
      w, h, [&](int, int) { return radiance; }, "constant");
}

// "Cosine sky" L(w) = max(0, w_z), each texel holding its exact average over the texel
// (solid-angle measure): (max(0, z_top)^2 - max(0, z_bottom)^2) / (2 (z_top - z_bottom)).
inline data::EnvironmentMap cosine_sky_map(int w, int h) {
  return make_map(
      w, h,
      [h](int, int y) {
        const double a = std::max(0.0, z_top(y, h)), b = std::max(0.0, z_bottom(y, h));
        return glm::vec3(
            static_cast<float>((a * a - b * b) / (2 * (z_top(y, h) - z_bottom(y, h)))));
      },
      "cosine sky");
}

// Closed form of the cosine sky's irradiance for a normal at angle g from +z:
// int max(0, z.w) max(0, n.w) dw = (2/3) (sin g + (pi - g) cos g). It is the first-order
// arc-cosine kernel (Cho and Saul 2009, "Kernel Methods for Deep Learning", J_1), rescaled from a
// Gaussian to the unit sphere (E_gauss = 3 E_sphere, 4 pi solid angle); checks: g = 0 gives
// 2 pi / 3 (int cos^2 over the hemisphere), g = pi gives 0.
inline double cosine_sky_irradiance(double g) {
  return 2.0 / 3.0 * (std::sin(g) + (kPi - g) * std::cos(g));
}

// Exact irradiance of a piecewise-constant map (rotated by rot about z) at an unoccluded point
// with normal n: sum over texels of L * int_texel max(0, n.w) dw, the inner integral by an
// m x m midpoint rule in (z, phi) (equal-area cells; error O(1/m^2) per texel, far below 1e-6
// relative for m = 8 on a 256 x 128 map).
inline glm::dvec3 exact_map_irradiance(const data::EnvironmentMap& map, float rot, glm::vec3 n,
                                       int m = 8) {
  const double c = std::cos(rot), s = std::sin(rot);
  const glm::dvec3 nm(c * n.x + s * n.y, -s * n.x + c * n.y, n.z);  // normal in the map frame
  glm::dvec3 sum(0.0);
  for (int y = 0; y < map.height; ++y) {
    const double zt = z_top(y, map.height), zb = z_bottom(y, map.height);
    for (int x = 0; x < map.width; ++x) {
      double acc = 0;
      for (int i = 0; i < m; ++i) {
        const double z = zt + (zb - zt) * (i + 0.5) / m, r = std::sqrt(std::max(0.0, 1 - z * z));
        for (int j = 0; j < m; ++j) {
          const double phi = 2 * kPi * (x + (j + 0.5) / m) / map.width;
          acc += std::max(0.0, nm.x * r * std::cos(phi) + nm.y * r * std::sin(phi) + nm.z * z);
        }
      }
      const double omega = 2 * kPi / map.width * (zt - zb);
      const float* t = map.texel(x, y);
      sum += glm::dvec3(t[0], t[1], t[2]) * (acc / (m * m) * omega);
    }
  }
  return sum;
}

// A square of side 2 * half at height z, normal +z, as a 2-triangle mesh.
inline data::MeshData quad(float half, float z) {
  data::MeshData m;
  m.name = "quad";
  m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

inline data::HeightField flat_field(int w, int h, float cell, float height) {
  data::HeightField f;
  f.width = w;
  f.height = h;
  f.cell_size = cell;
  f.heights.assign(static_cast<std::size_t>(w) * h, height);
  f.source = "flat";
  return f;
}

// Integral of f over the spherical cap {w : axis.w >= cos_alpha} by Gauss-Legendre in
// cos(theta) (n_t nodes) times n_phi uniform azimuths: exact to rounding for polynomials of low
// degree, O(h^2) for integrands with kinks.
template <class F>
double cap_integral(glm::dvec3 axis, double cos_alpha, int n_t, int n_phi, F&& f) {
  // Gauss-Legendre nodes on [-1, 1] (Newton on P_n).
  std::vector<double> xs(n_t), ws(n_t);
  for (int i = 0; i < n_t; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n_t + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n_t; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n_t * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    xs[i] = x;
    ws[i] = 2 / ((1 - x * x) * dp * dp);
  }
  // Frame around the axis.
  const glm::dvec3 a = glm::normalize(axis);
  const glm::dvec3 t = glm::normalize(std::abs(a.x) < 0.9 ? glm::cross(a, glm::dvec3(1, 0, 0))
                                                          : glm::cross(a, glm::dvec3(0, 1, 0)));
  const glm::dvec3 b = glm::cross(a, t);
  double sum = 0;
  const double half = (1 - cos_alpha) / 2;
  for (int i = 0; i < n_t; ++i) {
    const double z = cos_alpha + half * (xs[i] + 1), r = std::sqrt(std::max(0.0, 1 - z * z));
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / n_phi;
      const glm::dvec3 w = z * a + r * std::cos(phi) * t + r * std::sin(phi) * b;
      sum += ws[i] * half * (2 * kPi / n_phi) * f(w);
    }
  }
  return sum;
}

// |estimate - exact| <= k standard errors + slack (float rounding / quadrature). k = 4 for a
// single comparison; tests making hundreds of correlated comparisons (every SH coefficient of
// several estimates) use k = 5, so that the family fails by chance on well under 1% of seeds.
inline ::testing::AssertionResult within_error(double estimate, double se, double exact,
                                               double slack, double k = 4) {
  const double err = std::abs(estimate - exact);
  if (err <= k * se + slack) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "estimate " << estimate << " exact " << exact << " error " << err << " = " << err / se
         << " sigma (se " << se << ", slack " << slack << ")";
}

}  // namespace penumbra::reference::test
