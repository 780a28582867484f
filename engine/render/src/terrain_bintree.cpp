#include "penumbra/render/terrain_bintree.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace penumbra::render {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

bool has_midpoint(int ax, int ay, int bx, int by) {
  return (ax + bx) % 2 == 0 && (ay + by) % 2 == 0;
}

long long cross(int ux, int uy, int vx, int vy) {
  return static_cast<long long>(ux) * vy - static_cast<long long>(uy) * vx;
}

}  // namespace

float TerrainBintree::projected_pixels(float error, const glm::vec3& centre, float radius,
                                       const View& view) {
  // A vertical offset e at p, seen from the eye, moves on screen by e sin(beta) / |p - eye|
  // radians, beta the angle between the view ray and the vertical: e h / |p - eye|^2 with h the
  // horizontal distance. Over the sphere, h <= h_c + r and |p - eye| >= d_c - r.
  const glm::vec3 v = centre - view.eye;
  const float d = std::sqrt(glm::dot(v, v)) - radius;
  if (d <= 0) return std::numeric_limits<float>::infinity();
  const float h = std::sqrt(v.x * v.x + v.y * v.y) + radius;
  return error * view.focal_px * std::min(h, d) / (d * d);
}

template <class Fn>
void TerrainBintree::for_each_at_depth(int depth, Fn&& fn) const {
  const int n = size_ - 1;
  auto visit = [&](auto&& self, const Triangle& t, int d) -> void {
    if (d == depth) {
      fn(t);
      return;
    }
    if (outside(t)) return;
    const int mx = (t.ax + t.bx) / 2, my = (t.ay + t.by) / 2;
    self(self, Triangle{t.cx, t.cy, t.ax, t.ay, mx, my}, d + 1);
    self(self, Triangle{t.bx, t.by, t.cx, t.cy, mx, my}, d + 1);
  };
  visit(visit, Triangle{0, 0, n, n, n, 0}, 0);
  visit(visit, Triangle{n, n, 0, 0, 0, n}, 0);
}

bool TerrainBintree::inside(const Triangle& t) const {
  return std::max({t.ax, t.bx, t.cx}) <= width_ - 1 && std::max({t.ay, t.by, t.cy}) <= height_ - 1;
}

bool TerrainBintree::outside(const Triangle& t) const {
  return std::min({t.ax, t.bx, t.cx}) >= width_ - 1 || std::min({t.ay, t.by, t.cy}) >= height_ - 1;
}

glm::vec3 TerrainBintree::position(int x, int y) const {
  return glm::vec3(static_cast<float>(x) * cell_, static_cast<float>(y) * cell_,
                   heights_[static_cast<std::size_t>(y) * width_ + x]);
}

float TerrainBintree::triangle_error(const Triangle& t) const {
  auto h = [&](int x, int y) {
    return static_cast<double>(heights_[static_cast<std::size_t>(y) * width_ + x]);
  };
  // The plane through the three vertices, relative to a: h = ha + p (x - ax) + q (y - ay).
  const int ux = t.bx - t.ax, uy = t.by - t.ay, vx = t.cx - t.ax, vy = t.cy - t.ay;
  const double det = static_cast<double>(cross(ux, uy, vx, vy));
  const double ha = h(t.ax, t.ay), du = h(t.bx, t.by) - ha, dv = h(t.cx, t.cy) - ha;
  const double p = (du * vy - dv * uy) / det, q = (dv * ux - du * vx) / det;
  double worst = 0;
  const int x0 = std::min({t.ax, t.bx, t.cx}), x1 = std::max({t.ax, t.bx, t.cx});
  const int y0 = std::min({t.ay, t.by, t.cy}), y1 = std::max({t.ay, t.by, t.cy});
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const long long w0 = cross(t.bx - t.ax, t.by - t.ay, x - t.ax, y - t.ay);
      const long long w1 = cross(t.cx - t.bx, t.cy - t.by, x - t.bx, y - t.by);
      const long long w2 = cross(t.ax - t.cx, t.ay - t.cy, x - t.cx, y - t.cy);
      if ((w0 < 0 || w1 < 0 || w2 < 0) && (w0 > 0 || w1 > 0 || w2 > 0)) continue;
      worst = std::max(worst, std::abs(h(x, y) - (ha + p * (x - t.ax) + q * (y - t.ay))));
    }
  return static_cast<float>(worst);
}

void TerrainBintree::build(const data::HeightField& field) {
  size_ = depth_ = 0;
  error_.clear();
  radius_.clear();
  if (field.width < 2 || field.height < 2 ||
      field.heights.size() < static_cast<std::size_t>(field.width) * field.height)
    return;
  width_ = field.width;
  height_ = field.height;
  cell_ = field.cell_size;
  heights_.assign(field.heights.begin(),
                  field.heights.begin() + static_cast<std::ptrdiff_t>(width_) * height_);
  int n = 1;
  while (n < std::max(width_, height_) - 1) {
    n *= 2;
    depth_ += 2;
  }
  size_ = n + 1;
  error_.assign(static_cast<std::size_t>(size_) * size_, 0.0f);
  radius_.assign(error_.size(), 0.0f);
  // Finest level first, so that a midpoint's children are final before it takes their maximum.
  for (int depth = depth_ - 1; depth >= 0; --depth) {
    for_each_at_depth(depth, [&](const Triangle& t) {
      if (outside(t)) return;
      const int mx = (t.ax + t.bx) / 2, my = (t.ay + t.by) / 2;
      const std::size_t m = static_cast<std::size_t>(my) * size_ + mx;
      if (!inside(t)) {  // across the grid's border: always split
        error_[m] = kInfinity;
        return;
      }
      const float e = triangle_error(t);
      const glm::vec3 pm = position(mx, my);
      float& E = error_[m];
      float& R = radius_[m];
      E = std::max(E, e);
      for (const glm::ivec2 v :
           {glm::ivec2(t.ax, t.ay), glm::ivec2(t.bx, t.by), glm::ivec2(t.cx, t.cy)})
        R = std::max(R, glm::distance(position(v.x, v.y), pm) + e);
      if (depth + 1 == depth_) return;  // the children are grid cells: no midpoints
      for (const glm::ivec2 c : {glm::ivec2((t.cx + t.ax) / 2, (t.cy + t.ay) / 2),
                                 glm::ivec2((t.bx + t.cx) / 2, (t.by + t.cy) / 2)}) {
        const std::size_t ci = static_cast<std::size_t>(c.y) * size_ + c.x;
        E = std::max(E, error_[ci]);
        if (std::isfinite(error_[ci]))
          R = std::max(R, glm::distance(position(c.x, c.y), pm) + radius_[ci]);
      }
    });
  }
}

void TerrainBintree::refine(const Triangle& t, const View& view, const glm::vec4 (&planes)[6],
                            std::vector<std::uint32_t>& indices, std::size_t& count) const {
  if (outside(t)) return;
  if (has_midpoint(t.ax, t.ay, t.bx, t.by)) {
    const int mx = (t.ax + t.bx) / 2, my = (t.ay + t.by) / 2;
    const std::size_t m = static_cast<std::size_t>(my) * size_ + mx;
    const float e = error_[m];
    bool split = true;
    if (std::isfinite(e)) {
      const glm::vec3 c = position(mx, my);
      const float r = radius_[m];
      if (view.cull)
        for (const glm::vec4& p : planes)
          if (glm::dot(glm::vec3(p), c) + p.w < -r) return;  // S(m) holds t: t is not in view
      split = view.max_pixels <= 0 || (e > 0 && projected_pixels(e, c, r, view) > view.max_pixels);
    }
    if (split) {
      refine(Triangle{t.cx, t.cy, t.ax, t.ay, mx, my}, view, planes, indices, count);
      refine(Triangle{t.bx, t.by, t.cx, t.cy, mx, my}, view, planes, indices, count);
      return;
    }
  }
  // Counter-clockwise seen from above (+z).
  const bool ccw = cross(t.bx - t.ax, t.by - t.ay, t.cx - t.ax, t.cy - t.ay) > 0;
  auto index = [&](int x, int y) {
    return static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(width_) +
           static_cast<std::uint32_t>(x);
  };
  indices.push_back(index(t.ax, t.ay));
  indices.push_back(ccw ? index(t.bx, t.by) : index(t.cx, t.cy));
  indices.push_back(ccw ? index(t.cx, t.cy) : index(t.bx, t.by));
  ++count;
}

std::size_t TerrainBintree::triangulate(const View& view,
                                        std::vector<std::uint32_t>& indices) const {
  if (size_ == 0) return 0;
  // Frustum planes (Vulkan clip space: -w <= x, y <= w, 0 <= z <= w), normalised.
  glm::vec4 rows[4];
  for (int i = 0; i < 4; ++i)
    rows[i] = glm::vec4(view.view_proj[0][i], view.view_proj[1][i], view.view_proj[2][i],
                        view.view_proj[3][i]);
  glm::vec4 planes[6] = {rows[3] + rows[0], rows[3] - rows[0], rows[3] + rows[1],
                         rows[3] - rows[1], rows[2],           rows[3] - rows[2]};
  for (glm::vec4& p : planes) {
    const float len = glm::length(glm::vec3(p));
    if (len > 0) p /= len;
  }
  const int n = size_ - 1;
  std::size_t count = 0;
  refine(Triangle{0, 0, n, n, n, 0}, view, planes, indices, count);
  refine(Triangle{n, n, 0, 0, 0, n}, view, planes, indices, count);
  return count;
}

}  // namespace penumbra::render
