// The terrain benchmark's view of the ground truth (tests/terrain_shadow/terrain_reference.h,
// library penumbra_terrain_reference): one scene, one HDR map, reference irradiance at
// subsampled receivers computed once per run and cached, and the error summary of a method's
// irradiance grid against it. Everything the benchmark group "terrain" needs from the reference
// goes through here, so the terrain benchmark files do not depend on that library's details.
//
// Scene: "mountains" (fBm, 256 m across, about 1 m cells at 256 x 256; [Meier13] ch. 6), heights x 1,
// under ../shared/data/hdri/sunset.exr (the demo's map), unrotated. Receivers: every 8th texel
// (32 x 32 at 256 x 256), kSamples directions each (MIS), ground plane as in the accuracy tests.
// Threading: call from one thread (the benchmark's); the reference runs tbb::parallel_for.
#pragma once

#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/sh/basis.h"
#include "terrain_reference.h"

namespace penumbra::bench::terrain {

namespace tr = penumbra::terrain_reference;

inline constexpr const char* kSceneName = "mountains";
inline constexpr const char* kEnvironment = "sunset";
inline constexpr float kHeightScale = 1.0f;
inline constexpr int kStride = 8;      // receivers: every 8th texel along both axes
inline constexpr int kSamples = 2048;  // reference directions per receiver (per light)

struct ErrorSummary {
  std::optional<double> rel_rms, max_rel;  // see terrain_reference.h; empty: not computed
  std::optional<double> ref_rel_se;        // the reference's own relative standard error
};

struct Light {
  glm::vec3 centre;
  float radius;
  glm::vec3 radiance;
};

inline std::shared_ptr<const data::HeightField> load_scene(const std::string& name, int size) {
  return tr::load_terrain(name, size);
}

inline const data::EnvironmentMap& environment_map() {
  static const data::EnvironmentMap map = tr::load_hdri(kEnvironment);
  return map;
}
inline std::string environment_name() {
  return std::string(kEnvironment) + ".exr";
}

template <int N>
sh::CoeffsRgb<N> environment_sh() {
  return tr::environment_sh<N>(environment_map(), 0.0f);
}

inline tr::ReferenceOptions reference_options() {
  tr::ReferenceOptions o;
  o.samples = kSamples;
  return o;
}

inline std::string reference_description() {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "terrain_reference: Monte Carlo (Embree), every %dth texel, %d directions per "
                "receiver, ground plane",
                kStride, kSamples);
  return buf;
}

inline ErrorSummary to_summary(const tr::ErrorSummary& e) {
  return {e.rel_rms, e.max_rel, e.ref_rel_se};
}

// Environment irradiance error of a whole-field grid (size x size, row-major) of the scene.
inline ErrorSummary environment_error(int size, const std::vector<glm::vec3>& irradiance) {
  struct Cached {
    tr::ReceiverSet receivers;
    tr::ReferenceIrradiance reference;
  };
  static std::map<int, Cached> cache;
  auto it = cache.find(size);
  if (it == cache.end()) {
    const auto field = load_scene(kSceneName, size);
    tr::Lighting lighting;
    lighting.environment = &environment_map();
    Cached c;
    c.receivers = tr::texel_receivers(*field, kHeightScale, kStride * size / 256);
    c.reference =
        tr::reference_irradiance(*field, kHeightScale, c.receivers, lighting, reference_options());
    it = cache.emplace(size, std::move(c)).first;
  }
  return to_summary(
      tr::compare(irradiance, it->second.reference.texels, it->second.reference.environment));
}

// Error of the irradiance from spherical lights alone (no environment).
inline ErrorSummary light_error(int size, const std::vector<Light>& lights,
                                const std::vector<glm::vec3>& irradiance) {
  const auto field = load_scene(kSceneName, size);
  tr::Lighting lighting;
  for (const Light& l : lights) {
    reference::SphereLight s;
    s.center = l.centre;
    s.radius = l.radius;
    s.radiance = l.radiance;
    lighting.lights.push_back(s);
  }
  const tr::ReceiverSet receivers = tr::texel_receivers(*field, kHeightScale, kStride * size / 256);
  const tr::ReferenceIrradiance ref =
      tr::reference_irradiance(*field, kHeightScale, receivers, lighting, reference_options());
  return to_summary(tr::compare(irradiance, ref.texels, ref.lights));
}

}  // namespace penumbra::bench::terrain
