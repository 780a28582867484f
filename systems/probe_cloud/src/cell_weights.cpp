// Cell weights: barycentric coordinates in a tetrahedron ([Sukys14] sec. 4.2) and the outer
// cells' extrapolation along the hull normals ([Cupisz12]).
#include "penumbra/systems/probe_cloud/cell_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

namespace penumbra::probe_cloud {
namespace {

struct OuterFrame {
  glm::dvec3 p[3], n[3], x;  // triangle and query relative to p0
};

OuterFrame outer_frame(const data::ProbeCloud& cloud, std::uint32_t cell, const glm::vec3& q) {
  const data::ProbeCell& c = cloud.cells[cell];
  OuterFrame f;
  const glm::dvec3 origin(cloud.positions[static_cast<std::size_t>(c.vertices[0])]);
  for (int i = 0; i < 3; ++i) {
    const auto v = static_cast<std::size_t>(c.vertices[i]);
    f.p[i] = glm::dvec3(cloud.positions[v]) - origin;
    f.n[i] = glm::dvec3(cloud.hull_normals[v]);
  }
  f.x = glm::dvec3(q) - origin;
  return f;
}

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::dot(a, glm::cross(b, c));
}

// Coefficients (t^3, t^2, t, 1) of det[p_i + t n_i - x] ([Cupisz12]).
std::array<double, 4> cubic(const OuterFrame& f) {
  const glm::dvec3 a0 = f.p[0] - f.x, a1 = f.p[1] - f.x, a2 = f.p[2] - f.x;
  const glm::dvec3 &n0 = f.n[0], &n1 = f.n[1], &n2 = f.n[2];
  return {det3(n0, n1, n2), det3(a0, n1, n2) + det3(n0, a1, n2) + det3(n0, n1, a2),
          det3(n0, a1, a2) + det3(a0, n1, a2) + det3(a0, a1, n2), det3(a0, a1, a2)};
}

double eval(const std::array<double, 4>& c, double s) {
  return ((c[0] * s + c[1]) * s + c[2]) * s + c[3];
}

// Root of the polynomial in [lo, hi] where it changes sign: Newton steps kept inside the
// bracket, bisection when a step would leave it or shrink it too little (robust for any degree,
// including leading coefficients that vanish; a handful of steps instead of bisection's 50).
double bisect(const std::array<double, 4>& c, double lo, double hi) {
  const bool lo_negative = eval(c, lo) < 0;
  double s = 0.5 * (lo + hi), step_before = hi - lo;
  for (int i = 0; i < 100; ++i) {
    const double f = eval(c, s);
    if (f == 0) return s;
    if ((f < 0) == lo_negative) {
      lo = s;
    } else {
      hi = s;
    }
    const double df = (3 * c[0] * s + 2 * c[1]) * s + c[2];
    double next = df != 0 ? s - f / df : lo - 1;  // Newton, else force a bisection
    if (!(next > lo && next < hi) || std::abs(next - s) > 0.5 * step_before) next = 0.5 * (lo + hi);
    step_before = std::abs(next - s);
    s = next;
    if (step_before <= 1e-13 * std::max(1.0, std::abs(s)) || hi - lo <= 1e-15 * std::max(1.0, hi))
      return s;
  }
  return s;
}

// The smallest s > 0 with f(s) = 0 for f(0) < 0; infinity when f never reaches 0.
double smallest_positive_root(const std::array<double, 4>& c) {
  // Monotone pieces between the critical points (roots of 3 c0 s^2 + 2 c1 s + c2).
  double crit[2];
  int nc = 0;
  const double a = 3 * c[0], b = 2 * c[1], d = c[2];
  if (a != 0) {
    const double disc = b * b - 4 * a * d;
    if (disc >= 0) {
      const double r = std::sqrt(disc);
      const double q = -0.5 * (b + std::copysign(r, b));
      if (q != 0) {
        crit[nc++] = q / a;
        crit[nc++] = d / q;
      } else {
        crit[nc++] = 0;
      }
    }
  } else if (b != 0) {
    crit[nc++] = -d / b;
  }
  std::sort(crit, crit + nc);
  double lo = 0;
  for (int i = 0; i < nc; ++i) {
    if (crit[i] <= lo) continue;
    if (eval(c, crit[i]) >= 0) return eval(c, crit[i]) == 0 ? crit[i] : bisect(c, lo, crit[i]);
    lo = crit[i];
  }
  // Last piece, unbounded: double until the sign changes.
  double hi = std::max(2 * lo, 1.0);
  for (int i = 0; i < 80; ++i, hi *= 2) {
    if (eval(c, hi) >= 0) return bisect(c, lo, hi);
    lo = hi;
  }
  return std::numeric_limits<double>::infinity();
}

// Barycentric coordinates of x on the triangle q (its plane's projection).
std::array<double, 3> triangle_weights(const glm::dvec3 q[3], const glm::dvec3& x) {
  const glm::dvec3 normal = glm::cross(q[1] - q[0], q[2] - q[0]);
  const double area = glm::dot(normal, normal);
  if (!(area > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double w0 = glm::dot(glm::cross(q[1] - x, q[2] - x), normal) / area;
  const double w1 = glm::dot(glm::cross(q[2] - x, q[0] - x), normal) / area;
  return {w0, w1, 1.0 - w0 - w1};
}

}  // namespace

double outer_cell_parameter(const data::ProbeCloud& cloud, std::uint32_t cell, const glm::vec3& p) {
  const OuterFrame f = outer_frame(cloud, cell, p);
  std::array<double, 4> c = cubic(f);
  // f(0) = det[p_i - x] = -orient3d(p0, p1, p2, x): >= 0 on the inner side of the hull face.
  if (c[3] > 0) return -1.0;
  if (c[3] == 0) return 0.0;
  // Substitute t = L s (L: the triangle's size) so every coefficient has the same units.
  const double size = std::max({glm::length(f.p[1]), glm::length(f.p[2]), 1e-30});
  double scale = 1;
  for (int k = 3; k >= 0; --k, scale *= size)
    c[static_cast<std::size_t>(k)] *= scale / (size * size * size);
  return smallest_positive_root(c) * size;
}

std::array<float, 4> cell_weights(const data::ProbeCloud& cloud, std::uint32_t cell,
                                  const glm::vec3& p) {
  const data::ProbeCell& c = cloud.cells[cell];
  if (!c.outer()) {
    const glm::mat4& m = cloud.transforms[cell];
    const glm::vec3 l = glm::mat3(m) * (p - glm::vec3(m[3]));
    return {l.x, l.y, l.z, 1.0f - l.x - l.y - l.z};
  }
  const OuterFrame f = outer_frame(cloud, cell, p);
  const double t = outer_cell_parameter(cloud, cell, p);
  if (t < 0 || !std::isfinite(t)) {
    // Inner side (or never reached): the projection's weights, and weight[3] the most negative
    // so the walk steps to the tetrahedron behind the hull face.
    const std::array<double, 3> w = triangle_weights(f.p, f.x);
    const double lowest = std::min({w[0], w[1], w[2], 0.0}) - 1.0;
    if (t < 0) return {float(w[0]), float(w[1]), float(w[2]), float(lowest)};
    return {float(w[0]), float(w[1]), float(w[2]), 0.0f};
  }
  const glm::dvec3 moved[3] = {f.p[0] + t * f.n[0], f.p[1] + t * f.n[1], f.p[2] + t * f.n[2]};
  const std::array<double, 3> w = triangle_weights(moved, f.x);
  const double sum = w[0] + w[1] + w[2];
  return {float(w[0] / sum), float(w[1] / sum), float(w[2] / sum), 0.0f};
}

}  // namespace penumbra::probe_cloud
