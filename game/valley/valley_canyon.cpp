#include "penumbra/game/valley_canyon.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/game/valley_rules.h"

namespace penumbra::game {
namespace {

float distance_to_segment(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
  const glm::vec2 ab = b - a;
  const float t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-6f), 0.0f, 1.0f);
  return glm::length(p - (a + t * ab));
}

// 1 within the half width, 0 beyond twice it, smooth between.
float profile(float d, float half_width) {
  const float t = std::clamp((d - half_width) / half_width, 0.0f, 1.0f);
  return 1.0f - t * t * (3.0f - 2.0f * t);
}

}  // namespace

void canyon_axis(glm::vec2 centre, float width, const CanyonConfig& c, glm::vec2& a, glm::vec2& b) {
  a = centre + width * c.from;
  b = centre + width * c.to;
}

void carve_canyon(data::HeightField& f, glm::vec3 origin, float height_scale,
                  const CanyonConfig& c) {
  if (f.width < 2 || f.height < 2 || !(height_scale > 0)) return;
  const float width = f.cell_size * static_cast<float>(f.width - 1);
  const glm::vec2 centre = glm::vec2(origin) + 0.5f * width;
  glm::vec2 a, b;
  canyon_axis(centre, width, c, a, b);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::vec2 p = glm::vec2(origin) + f.cell_size * glm::vec2(x, y);
      f.at(x, y) -= c.depth / height_scale * profile(distance_to_segment(p, a, b), c.half_width);
    }
}

std::vector<glm::vec3> canyon_probes(float width, const CanyonConfig& c) {
  const float length = width * glm::length(c.to - c.from);
  const int n = std::max(2, static_cast<int>(length / std::max(c.probe_spacing, 1.0f)) + 1);
  std::vector<glm::vec3> out;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 p =
        c.from + (c.to - c.from) * (static_cast<float>(i) / static_cast<float>(n - 1));
    for (float h : c.probe_heights) out.emplace_back(p, h);
  }
  return out;
}

ArchShape make_arch(glm::vec3 base, glm::vec2 axis, float radius, float thickness) {
  constexpr int kAlong = 32, kAround = 10, kSpheres = 19;
  const float pi = std::numbers::pi_v<float>;
  const glm::vec3 across = glm::normalize(glm::vec3(-axis.y, axis.x, 0.0f));
  const glm::vec3 along = glm::normalize(glm::vec3(axis, 0.0f)), up(0, 0, 1);
  auto centre_line = [&](float t) {  // t in [0, pi]: from one foot over the top to the other
    return base + radius * (std::cos(t) * across + std::sin(t) * up);
  };
  ArchShape s;
  s.mesh = std::make_shared<data::MeshData>();
  s.mesh->name = "canyon_arch";
  for (int i = 0; i <= kAlong; ++i) {
    const float t = pi * static_cast<float>(i) / kAlong;
    const glm::vec3 c = centre_line(t);
    const glm::vec3 out = std::cos(t) * across + std::sin(t) * up;  // away from the arc's centre
    for (int j = 0; j < kAround; ++j) {
      const float u = 2 * pi * static_cast<float>(j) / kAround;
      const glm::vec3 n = std::cos(u) * out + std::sin(u) * along;
      s.mesh->positions.push_back(c + thickness * n);
      s.mesh->normals.push_back(n);
    }
  }
  for (int i = 0; i < kAlong; ++i)
    for (int j = 0; j < kAround; ++j) {
      const auto v = [&](int a, int b) {
        return static_cast<std::uint32_t>(a * kAround + (b % kAround));
      };
      s.mesh->indices.insert(s.mesh->indices.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j),
                                                     v(i + 1, j + 1), v(i, j + 1)});
    }
  // The sphere set: spheres on the centre line from foot to foot, a tenth larger than the tube
  // so that the surface lies within a tenth of the thickness of one (valley_canyon_test).
  s.spheres = std::make_shared<std::vector<data::Sphere>>();
  for (int i = 0; i < kSpheres; ++i)
    s.spheres->push_back(
        {centre_line(pi * static_cast<float>(i) / (kSpheres - 1)), thickness * 1.1f, -1});
  return s;
}

std::vector<ArchShape> canyon_arches(const components::Terrain& t, const CanyonConfig& c) {
  std::vector<ArchShape> out;
  if (!t.heights || c.arches < 1) return out;
  const float width = t.heights->cell_size * static_cast<float>(t.heights->width - 1);
  const glm::vec2 centre = glm::vec2(t.origin) + 0.5f * width;
  glm::vec2 a, b;
  canyon_axis(centre, width, c, a, b);
  const glm::vec2 axis = glm::normalize(b - a);
  for (int k = 0; k < c.arches; ++k) {
    const glm::vec2 p = a + (b - a) * (static_cast<float>(k) + 1.0f) / (c.arches + 1.0f);
    out.push_back(
        make_arch(glm::vec3(p, ground_height(t, p)), axis, c.arch_radius, c.arch_thickness));
  }
  return out;
}

void add_canyon_arches(ecs::World& world, const CanyonConfig& c) {
  const components::Terrain* terrain = nullptr;
  world.query<const components::Terrain>().each([&](const components::Terrain& t) {
    if (!terrain && t.heights) terrain = &t;
  });
  if (!terrain) return;
  for (const ArchShape& arch : canyon_arches(*terrain, c)) {
    auto points = std::make_shared<const std::vector<glm::vec3>>(arch.mesh->positions);
    auto normals = std::make_shared<const std::vector<glm::vec3>>(arch.mesh->normals);
    world.create_with(components::Transform{}, components::MeshInstance{arch.mesh},
                      components::Material{c.arch_albedo, 0.0f},
                      components::SphereSet{arch.spheres},
                      components::Receiver{std::move(points), std::move(normals)},
                      components::ReceiverLighting{}, components::VertexLighting{});
  }
}

}  // namespace penumbra::game
