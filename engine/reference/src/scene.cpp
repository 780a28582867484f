// Scene validation and the Embree 3 BVH (robust traversal, high build quality).
#include "penumbra/reference/scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "common.h"
#include "penumbra/data/finite.h"

namespace penumbra::reference {
namespace {

std::string label(const char* kind, std::size_t i, const std::string& name) {
  std::string s = std::string(kind) + "[" + std::to_string(i) + "]";
  if (!name.empty()) s += " \"" + name + "\"";
  return s;
}
[[noreturn]] void fail(const std::string& what, const std::string& why) {
  throw std::invalid_argument("reference::Scene: " + what + ": " + why);
}
using data::finite;
std::string str(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g)", v.x, v.y, v.z);
  return buf;
}
std::string num(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
void check_radius(const std::string& what, float r) {
  if (!std::isfinite(r) || !(r > 0)) fail(what, "radius " + num(r) + " must be finite and > 0");
}
void check_albedo(const std::string& what, const glm::vec3& a) {
  for (int c = 0; c < 3; ++c) {
    if (!(a[c] >= 0 && a[c] <= 1)) fail(what, "albedo " + str(a) + " must be finite and in [0, 1]");
  }
}
using detail::black;
void validate(const SceneDesc& d) {
  for (std::size_t i = 0; i < d.height_fields.size(); ++i) {
    const auto& h = d.height_fields[i];
    const std::string what = label("height_fields", i, h.field.source);
    if (h.field.width < 2 || h.field.height < 2) {
      fail(what, "size " + std::to_string(h.field.width) + "x" + std::to_string(h.field.height) +
                     " is smaller than 2x2");
    }
    const std::size_t n = static_cast<std::size_t>(h.field.width) * h.field.height;
    if (h.field.heights.size() != n) {
      fail(what, "heights holds " + std::to_string(h.field.heights.size()) + " values, expected " +
                     std::to_string(n));
    }
    if (!std::isfinite(h.field.cell_size) || !(h.field.cell_size > 0)) {
      fail(what, "cell_size " + num(h.field.cell_size) + " must be finite and > 0");
    }
    if (!finite(h.origin)) fail(what, "origin " + str(h.origin) + " is not finite");
    check_albedo(what, h.albedo);
    for (std::size_t k = 0; k < n; ++k) {
      if (!std::isfinite(h.field.heights[k])) {
        fail(what, "height at (" + std::to_string(k % h.field.width) + ", " +
                       std::to_string(k / h.field.width) + ") is not finite");
      }
    }
  }
  for (std::size_t i = 0; i < d.meshes.size(); ++i) {
    const auto& m = d.meshes[i];
    const std::string what = label("meshes", i, m.mesh.name);
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        if (!std::isfinite(m.transform[c][r])) fail(what, "transform is not finite");
      }
    }
    check_albedo(what, m.albedo);
    for (std::size_t k = 0; k < m.mesh.positions.size(); ++k) {
      if (!finite(m.mesh.positions[k]))
        fail(what, "position " + std::to_string(k) + " is not finite");
    }
    if (m.mesh.indices.size() % 3 != 0) {
      fail(what, std::to_string(m.mesh.indices.size()) + " indices is not a multiple of 3");
    }
    for (std::size_t k = 0; k < m.mesh.indices.size(); ++k) {
      if (m.mesh.indices[k] >= m.mesh.positions.size()) {
        fail(what, "index " + std::to_string(k) + " = " + std::to_string(m.mesh.indices[k]) +
                       " is out of range (" + std::to_string(m.mesh.positions.size()) +
                       " positions)");
      }
    }
  }
  for (std::size_t i = 0; i < d.spheres.size(); ++i) {
    const auto& s = d.spheres[i];
    const std::string what = label("spheres", i, s.name);
    if (!finite(s.center)) fail(what, "center " + str(s.center) + " is not finite");
    check_radius(what, s.radius);
    check_albedo(what, s.albedo);
  }
  for (std::size_t i = 0; i < d.lights.size(); ++i) {
    const auto& l = d.lights[i];
    const std::string what = label("lights", i, l.name);
    if (!finite(l.center)) fail(what, "center " + str(l.center) + " is not finite");
    check_radius(what, l.radius);
    if (!finite(l.radiance) || l.radiance.x < 0 || l.radiance.y < 0 || l.radiance.z < 0) {
      fail(what, "radiance " + str(l.radiance) + " must be finite and >= 0");
    }
  }
}

void on_embree_error(void*, RTCError code, const char* message) {
  // Errors are also polled with rtcGetDeviceError after each build step; nothing to do here
  // but keep Embree from printing.
  (void)code;
  (void)message;
}

}  // namespace

struct Scene::Bvh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  // For Scene::first_hit: the albedo of each geometry (by Embree geomID), and the spheres'
  // centres and albedos (one sphere geometry, by primID).
  std::vector<glm::vec3> albedo;
  unsigned sphere_geom = RTC_INVALID_GEOMETRY_ID;
  std::vector<glm::vec4> spheres;  // centre, radius
  std::vector<glm::vec3> sphere_albedo;
  ~Bvh() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* step) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) {
      throw std::runtime_error(std::string("reference::Scene: Embree failed in ") + step +
                               " (error " + std::to_string(static_cast<int>(e)) + ")");
    }
  }
  // Adds a triangle geometry; returns pointers to fill (vertices xyz, indices).
  RTCGeometry add_triangles(std::size_t vertices, std::size_t triangles, float*& v,
                            unsigned*& idx) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                    3 * sizeof(float), vertices));
    idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles));
    check("allocating a triangle buffer");
    return g;
  }
  // Commits and attaches g; returns its geomID (ids are dense, from 0, in attach order).
  unsigned attach(RTCGeometry g, const glm::vec3& geom_albedo) {
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    check("committing a geometry");
    if (albedo.size() <= id) albedo.resize(id + 1, glm::vec3(0.0f));
    albedo[id] = geom_albedo;
    return id;
  }
};

Scene::Scene(const SceneDesc& desc) : bvh_(std::make_unique<Bvh>()) {
  validate(desc);
  if (desc.environment) {
    environment_ =
        std::make_unique<EnvironmentSampler>(desc.environment->map, desc.environment->rotation_z);
  }
  lights_ = desc.lights;

  bvh_->device = rtcNewDevice(nullptr);
  if (!bvh_->device) {
    throw std::runtime_error("reference::Scene: rtcNewDevice failed (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(bvh_->device, on_embree_error, nullptr);
  bvh_->scene = rtcNewScene(bvh_->device);
  rtcSetSceneFlags(bvh_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(bvh_->scene, RTC_BUILD_QUALITY_HIGH);
  bvh_->check("creating the scene");

  auto grow = [&](float a, float b, float c) {
    extent_ = std::max({extent_, std::fabs(a), std::fabs(b), std::fabs(c)});
  };
  for (const HeightFieldInstance& h : desc.height_fields) {
    const int w = h.field.width, hh = h.field.height;
    const std::size_t tris = 2 * static_cast<std::size_t>(w - 1) * (hh - 1);
    float* v = nullptr;
    unsigned* idx = nullptr;
    RTCGeometry g = bvh_->add_triangles(static_cast<std::size_t>(w) * hh, tris, v, idx);
    for (int y = 0; y < hh; ++y) {
      for (int x = 0; x < w; ++x) {
        float* p = v + 3 * (static_cast<std::size_t>(y) * w + x);
        p[0] = h.origin.x + x * h.field.cell_size;
        p[1] = h.origin.y + y * h.field.cell_size;
        p[2] = h.origin.z + h.field.at(x, y);
        grow(p[0], p[1], p[2]);
      }
    }
    unsigned* t = idx;
    for (int y = 0; y + 1 < hh; ++y) {
      for (int x = 0; x + 1 < w; ++x) {
        const auto a = static_cast<unsigned>(y * w + x), b = a + 1, c = a + w, d = c + 1;
        t[0] = a, t[1] = b, t[2] = d;  // split along (x, y)-(x+1, y+1)
        t[3] = a, t[4] = d, t[5] = c;
        t += 6;
      }
    }
    bvh_->attach(g, h.albedo);
    reflects_ = reflects_ || !black(h.albedo);
    triangles_ += tris;
  }
  for (const MeshInstance& m : desc.meshes) {
    if (m.mesh.indices.empty()) continue;
    const std::size_t tris = m.mesh.indices.size() / 3;
    float* v = nullptr;
    unsigned* idx = nullptr;
    RTCGeometry g = bvh_->add_triangles(m.mesh.positions.size(), tris, v, idx);
    for (std::size_t k = 0; k < m.mesh.positions.size(); ++k) {
      const glm::vec4 p = m.transform * glm::vec4(m.mesh.positions[k], 1.0f);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        fail(label("meshes", static_cast<std::size_t>(&m - desc.meshes.data()), m.mesh.name),
             "transformed position " + std::to_string(k) + " is not finite");
      }
      v[3 * k] = p.x, v[3 * k + 1] = p.y, v[3 * k + 2] = p.z;
      grow(p.x, p.y, p.z);
    }
    std::copy(m.mesh.indices.begin(), m.mesh.indices.end(), idx);
    bvh_->attach(g, m.albedo);
    reflects_ = reflects_ || !black(m.albedo);
    triangles_ += tris;
  }
  if (!desc.spheres.empty()) {
    RTCGeometry g = rtcNewGeometry(bvh_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), desc.spheres.size()));
    bvh_->check("allocating the sphere buffer");
    for (std::size_t k = 0; k < desc.spheres.size(); ++k) {
      const SphereOccluder& s = desc.spheres[k];
      v[4 * k] = s.center.x, v[4 * k + 1] = s.center.y, v[4 * k + 2] = s.center.z;
      v[4 * k + 3] = s.radius;
      grow(std::fabs(s.center.x) + s.radius, std::fabs(s.center.y) + s.radius,
           std::fabs(s.center.z) + s.radius);
      bvh_->spheres.emplace_back(s.center, s.radius);
      bvh_->sphere_albedo.push_back(s.albedo);
      reflects_ = reflects_ || !black(s.albedo);
    }
    bvh_->sphere_geom = bvh_->attach(g, glm::vec3(0.0f));
  }
  rtcCommitScene(bvh_->scene);
  bvh_->check("building the BVH");
}

Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

bool Scene::occluded(const glm::vec3& origin, const glm::vec3& dir, float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
  ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
  ray.tnear = 0;
  ray.tfar = t_max;
  ray.time = 0;
  ray.mask = ~0u;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(bvh_->scene, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

namespace {
RTCRayHit intersect(RTCScene scene, const glm::vec3& origin, const glm::vec3& dir, float t_max) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = origin.x, rh.ray.org_y = origin.y, rh.ray.org_z = origin.z;
  rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
  rh.ray.tnear = 0;
  rh.ray.tfar = t_max;
  rh.ray.time = 0;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  return rh;
}
}  // namespace

float Scene::hit_distance(const glm::vec3& origin, const glm::vec3& dir, float t_max) const {
  const RTCRayHit rh = intersect(bvh_->scene, origin, dir, t_max);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::numeric_limits<float>::infinity();
  return rh.ray.tfar;
}

Hit Scene::first_hit(const glm::vec3& origin, const glm::vec3& dir, float t_max) const {
  const RTCRayHit rh = intersect(bvh_->scene, origin, dir, t_max);
  Hit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.distance = rh.ray.tfar;
  glm::dvec3 n;
  if (rh.hit.geomID == bvh_->sphere_geom) {
    // From the centre, in double (Embree's Ng for spheres is the same direction, in float).
    const glm::vec4& c = bvh_->spheres[rh.hit.primID];
    const glm::dvec3 p = glm::dvec3(origin) + double(out.distance) * glm::dvec3(dir);
    n = p - glm::dvec3(c.x, c.y, c.z);
    out.albedo = bvh_->sphere_albedo[rh.hit.primID];
  } else {
    n = glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);  // the world-space face normal
    out.albedo = bvh_->albedo[rh.hit.geomID];
  }
  const double len = glm::length(n);
  // A degenerate normal (a hit at a sphere's centre cannot happen; a zero-area triangle is
  // never hit by Embree) falls back to facing the ray.
  n = len > 0 ? n / len : -glm::normalize(glm::dvec3(dir));
  if (glm::dot(n, glm::dvec3(dir)) > 0) n = -n;
  out.normal = glm::vec3(n);
  return out;
}

}  // namespace penumbra::reference
