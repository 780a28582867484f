#include "penumbra/systems/spherical_lights/reflector_samples.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "penumbra/data/finite.h"

namespace penumbra::spherical_lights {
namespace {

std::string mesh_name(const data::MeshData& m) {
  return "mesh \"" + (m.name.empty() ? std::string("(unnamed)") : m.name) + "\"";
}

using data::finite;

struct Triangle {
  glm::vec3 a, e1, e2, face_normal;  // face_normal: unnormalised, by the winding
  std::uint32_t i0, i1, i2;
};

struct Hit {
  float t;
  bool back;  // the ray leaves through the triangle's back side (normal along the ray)
  std::uint32_t tri;
  float u, v;
};

// Moller-Trumbore, both sides; t > 0.
bool intersect(const Triangle& tri, const glm::vec3& o, const glm::vec3& d, float& t, float& u,
               float& v) {
  const glm::vec3 p = glm::cross(d, tri.e2);
  const float det = glm::dot(tri.e1, p);
  if (std::abs(det) < 1e-20f) return false;
  const float inv = 1.0f / det;
  const glm::vec3 s = o - tri.a;
  u = glm::dot(s, p) * inv;
  constexpr float kEdge = 1e-6f;  // a ray along a shared edge hits both triangles: no gaps
  if (u < -kEdge || u > 1 + kEdge) return false;
  const glm::vec3 q = glm::cross(s, tri.e1);
  v = glm::dot(d, q) * inv;
  if (v < -kEdge || u + v > 1 + kEdge) return false;
  t = glm::dot(tri.e2, q) * inv;
  return t > 0;
}

// [Guerrero08] eq. 2: the sphere nearest p by |p - x| / r.
std::size_t nearest_sphere(const glm::vec3& p, std::span<const data::Sphere> spheres) {
  std::size_t best = 0;
  float best_d = std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const float d = glm::length(p - spheres[k].centre) / spheres[k].radius;
    if (d < best_d) best_d = d, best = k;
  }
  return best;
}

}  // namespace

std::vector<glm::vec3> geodesic_directions(int frequency) {
  if (frequency < 1) throw std::invalid_argument("geodesic_directions: frequency must be >= 1");
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  const std::array<glm::vec3, 12> v = {
      glm::vec3(-1, g, 0), glm::vec3(1, g, 0), glm::vec3(-1, -g, 0), glm::vec3(1, -g, 0),
      glm::vec3(0, -1, g), glm::vec3(0, 1, g), glm::vec3(0, -1, -g), glm::vec3(0, 1, -g),
      glm::vec3(g, 0, -1), glm::vec3(g, 0, 1), glm::vec3(-g, 0, -1), glm::vec3(-g, 0, 1)};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  std::vector<glm::vec3> out;
  const float f = static_cast<float>(frequency);
  for (const auto& face : faces) {
    for (int i = 0; i <= frequency; ++i) {
      for (int j = 0; i + j <= frequency; ++j) {
        const int k = frequency - i - j;
        const glm::vec3 p = glm::normalize((static_cast<float>(i) * v[face[0]] +
                                            static_cast<float>(j) * v[face[1]] +
                                            static_cast<float>(k) * v[face[2]]) /
                                           f);
        bool seen = false;  // shared edge and corner points appear in several faces
        for (const glm::vec3& q : out) seen = seen || glm::dot(p - q, p - q) < 1e-8f;
        if (!seen) out.push_back(p);
      }
    }
  }
  return out;
}

ReflectorSamples sample_reflector(const data::MeshData& mesh, std::span<const data::Sphere> spheres,
                                  const ReflectorSettings& settings, glm::vec3 albedo_override) {
  const std::string name = mesh_name(mesh);
  if (mesh.indices.size() < 3 || mesh.indices.size() % 3 != 0) {
    throw std::invalid_argument(name + ": no triangles (index count " +
                                std::to_string(mesh.indices.size()) + ")");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i])) {
      throw std::invalid_argument(name + ": position " + std::to_string(i) + " is not finite");
    }
  }
  for (std::uint32_t idx : mesh.indices) {
    if (idx >= mesh.positions.size()) {
      throw std::invalid_argument(name + ": index " + std::to_string(idx) + " out of range (" +
                                  std::to_string(mesh.positions.size()) + " positions)");
    }
  }
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    if (!finite(spheres[k].centre) || !std::isfinite(spheres[k].radius) ||
        !(spheres[k].radius > 0)) {
      throw std::invalid_argument(name + ": sphere " + std::to_string(k) +
                                  " needs a finite centre and a finite radius > 0");
    }
  }

  std::vector<Triangle> tris;
  tris.reserve(mesh.indices.size() / 3);
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const std::uint32_t i0 = mesh.indices[i], i1 = mesh.indices[i + 1], i2 = mesh.indices[i + 2];
    const glm::vec3 a = mesh.positions[i0], b = mesh.positions[i1], c = mesh.positions[i2];
    tris.push_back({a, b - a, c - a, glm::cross(b - a, c - a), i0, i1, i2});
  }
  const std::vector<glm::vec3> vertex_normals = data::vertex_normals(mesh);
  const glm::vec3 albedo =
      albedo_override.x >= 0 && albedo_override.y >= 0 && albedo_override.z >= 0
          ? glm::clamp(albedo_override, 0.0f, 1.0f)
          : glm::clamp(glm::vec3(mesh.base_color), 0.0f, 1.0f);

  ReflectorSamples out;
  out.directions = geodesic_directions(settings.geodesic_frequency);
  out.lights.resize(spheres.size());
  const std::size_t m = out.directions.size();

  tbb::parallel_for(std::size_t{0}, spheres.size(), [&](std::size_t s) {
    const data::Sphere& sl = spheres[s];
    SphereSamples& dst = out.lights[s];
    dst.centre = sl.centre;
    dst.radius = sl.radius;
    dst.positions.assign(m, glm::vec3(0.0f));
    dst.normals.assign(m, glm::vec3(0.0f));
    dst.albedo.assign(m, glm::vec3(0.0f));
    dst.valid.assign(m, 0);
    std::vector<Hit> hits;
    auto cast = [&](const glm::vec3& dir) {
      hits.clear();
      for (std::uint32_t t = 0; t < tris.size(); ++t) {
        float th, u, v;
        if (intersect(tris[t], sl.centre, dir, th, u, v)) {
          hits.push_back({th, glm::dot(tris[t].face_normal, dir) > 0, t, u, v});
        }
      }
    };
    auto in_segment = [&](const Hit& h, const glm::vec3& dir) {
      return nearest_sphere(sl.centre + h.t * dir, spheres) == s;
    };
    for (std::size_t j = 0; j < m; ++j) {
      const glm::vec3 w = out.directions[j];
      // [Guerrero08] sec. 6.2: directions covered by an intersecting sphere of the set.
      const glm::vec3 on_sphere = sl.centre + sl.radius * w;
      bool covered = false;
      for (std::size_t k = 0; k < spheres.size() && !covered; ++k) {
        covered = k != s && glm::length(on_sphere - spheres[k].centre) < spheres[k].radius;
      }
      if (covered) continue;
      // [Guerrero08] sec. 4.2, the three ray cases.
      cast(w);
      const Hit* chosen = nullptr;
      glm::vec3 dir = w;
      bool any_back = false;
      for (const Hit& h : hits) {
        if (!h.back) continue;
        any_back = true;
        if (in_segment(h, w) && (chosen == nullptr || h.t > chosen->t)) chosen = &h;
      }
      if (chosen == nullptr && !any_back) {  // case 3: the centre is outside the object
        dir = -w;
        cast(dir);
        for (const Hit& h : hits) {
          if (!h.back && (chosen == nullptr || h.t < chosen->t)) chosen = &h;
        }
        if (chosen != nullptr && !in_segment(*chosen, dir)) chosen = nullptr;
      }
      if (chosen == nullptr) continue;
      const Triangle& tri = tris[chosen->tri];
      glm::vec3 n = (1 - chosen->u - chosen->v) * vertex_normals[tri.i0] +
                    chosen->u * vertex_normals[tri.i1] + chosen->v * vertex_normals[tri.i2];
      if (glm::dot(n, tri.face_normal) <= 0 || glm::length(n) < 1e-12f) n = tri.face_normal;
      dst.positions[j] = sl.centre + chosen->t * dir;
      dst.normals[j] = glm::normalize(n);
      dst.albedo[j] = albedo;
      dst.valid[j] = 1;
    }
  });
  return out;
}

}  // namespace penumbra::spherical_lights
