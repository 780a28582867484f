#include "penumbra/systems/spherical_lights/reflector_lighting.h"

#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace penumbra::spherical_lights {

template <int N>
ReflectorLighting<N>::ReflectorLighting(std::span<const glm::vec3> directions, int strata)
    : cells_(directions, strata) {}

template <int N>
sh::CoeffsRgb<N> ReflectorLighting<N>::albedo_sh(const SphereSamples& sl) const {
  return cells_.project(sl.albedo);
}

template <int N>
std::vector<sh::CoeffsRgb<N>> ReflectorLighting<N>::update(
    const ReflectorSamples& object, const ObjectPose& pose,
    const blocker_accumulation::BlockerAccumulation<N>& blockers,
    const sh::CoeffsRgb<N>& environment, std::vector<std::vector<glm::vec3>>* reflected_out,
    const sh::Coeffs<N>* extra_log, const std::function<bool(const glm::vec3&)>& buried) const {
  if (static_cast<int>(object.directions.size()) != cells_.cells()) {
    throw std::invalid_argument("ReflectorLighting::update: the object's samples have " +
                                std::to_string(object.directions.size()) +
                                " directions, the cells " + std::to_string(cells_.cells()));
  }
  std::vector<sh::CoeffsRgb<N>> out(object.lights.size());
  if (reflected_out) reflected_out->assign(object.lights.size(), {});
  std::vector<glm::vec3> points, normals, irradiance;
  std::vector<int> slot;
  std::vector<glm::vec3> reflected;
  for (std::size_t s = 0; s < object.lights.size(); ++s) {
    const SphereSamples& sl = object.lights[s];
    points.clear(), normals.clear(), slot.clear();
    for (std::size_t j = 0; j < sl.valid.size(); ++j) {
      if (!sl.valid[j]) continue;
      points.push_back(pose.rotation * (pose.scale * sl.positions[j]) + pose.translation);
      normals.push_back(glm::normalize(pose.rotation * sl.normals[j]));
      slot.push_back(static_cast<int>(j));
    }
    irradiance.assign(points.size(), glm::vec3(0.0f));
    for (std::size_t k = 0; k < points.size(); ++k) {  // [Guerrero08] eq. 3-8
      irradiance[k] =
          buried && buried(points[k])
              ? glm::vec3(0.0f)
              : blockers.irradiance(environment, points[k], normals[k], nullptr, extra_log);
    }
    reflected.assign(sl.valid.size(), glm::vec3(0.0f));
    for (std::size_t k = 0; k < slot.size(); ++k) {
      reflected[slot[k]] = irradiance[k] * (1.0f / 3.14159265358979f);
    }
    out[s] = albedo_product<N>(cells_.project(reflected), albedo_sh(sl));  // eq. 10-11
    if (reflected_out) (*reflected_out)[s] = reflected;
  }
  return out;
}

template <int N>
void ReflectorLighting<N>::place(const ReflectorSamples& object, const ObjectPose& pose,
                                 std::span<const sh::CoeffsRgb<N>> radiance,
                                 std::uint32_t object_id, std::vector<SphereLightSource<N>>& out) {
  if (radiance.size() != object.lights.size()) {
    throw std::invalid_argument("ReflectorLighting::place: " + std::to_string(radiance.size()) +
                                " radiance vectors for " + std::to_string(object.lights.size()) +
                                " spherical lights");
  }
  const glm::mat3 to_local = glm::transpose(pose.rotation);  // [Guerrero08] sec. 7.1
  for (std::size_t s = 0; s < object.lights.size(); ++s) {
    SphereLightSource<N> l;
    l.centre = pose.rotation * (pose.scale * object.lights[s].centre) + pose.translation;
    l.radius = pose.scale * object.lights[s].radius;
    l.object = object_id;
    l.to_local = to_local;
    l.radiance = radiance[s];
    out.push_back(l);
  }
}

template class ReflectorLighting<3>;
template class ReflectorLighting<4>;
template class ReflectorLighting<5>;

}  // namespace penumbra::spherical_lights
