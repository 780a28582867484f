#include "terrain_tuner.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "sky_split.h"

namespace penumbra::tune {

namespace ts = terrain_shadow;

namespace {

ts::TerrainShadowConfig config_of(const settings::TerrainTuning& t) {
  ts::TerrainShadowConfig c;
  c.method = t.horizon == "march" ? ts::HorizonMethod::kMarch : ts::HorizonMethod::kSweep;
  c.azimuths = t.azimuths;
  c.pyramid.level_step = t.level_step;
  return c;
}

template <int N>
Evaluation run_terrain(const TuneScene& s, const SplitSky& sky, const settings::TerrainTuning& t,
                       const TuneOptions& o, const std::vector<std::size_t>& texels,
                       const std::vector<glm::vec3>& ref) {
  const sh::CoeffsRgb<N> radiance = environment_sh<N>(sky.rest, s.rotation_rad());
  ts::TerrainShadowing<N> method(config_of(t));
  std::vector<glm::vec3> e;
  std::vector<float> horizons;
  Evaluation out;
  out.ms = min_ms(o.timing_reps, [&] {
    method.update(s.field, s.height_scale);
    method.shade_environment(radiance, e);
    for (const KeyLight& k : sky.keys) {  // as terrain_shadow.compose adds them
      method.key_light_horizons(k.direction, horizons);
      method.add_key_light(k.direction, k.angular_radius, k.irradiance, horizons, e);
    }
  });
  out.cost = out.ms;
  std::vector<glm::vec3> at(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) at[i] = e[texels[i]];
  out.error = rel_rms(at, ref);
  return out;
}

}  // namespace

TerrainTuner::TerrainTuner(const TuneScene& scene, const TuneOptions& options)
    : scene_(scene),
      options_(options),
      sky_(split_sky(scene.environment, scene.rotation_rad(), options.key_lights)) {
  knobs_ = {{"horizon", {"march_ls4", "march_ls2", "sweep"}},
            {"azimuths", {"4", "8", "16", "32"}},
            {"bands", {"3", "4", "5", "6"}}};
  const data::HeightField& f = *scene.field;
  const float hs = scene.height_scale, cs = f.cell_size;
  // Receivers: every stride-th texel from stride / 2, central-difference normals
  // (TerrainShadowing::compute_normals, reference::height_field_receivers).
  std::vector<reference::Receiver> receivers;
  for (int y = scene.stride / 2; y < f.height; y += scene.stride)
    for (int x = scene.stride / 2; x < f.width; x += scene.stride) {
      const int xa = std::max(x - 1, 0), xb = std::min(x + 1, f.width - 1);
      const int ya = std::max(y - 1, 0), yb = std::min(y + 1, f.height - 1);
      const float dx = hs * (f.at(xb, y) - f.at(xa, y)) / ((xb - xa) * cs);
      const float dy = hs * (f.at(x, yb) - f.at(x, ya)) / ((yb - ya) * cs);
      reference::Receiver r;
      r.position = {x * cs, y * cs, hs * f.at(x, y)};
      r.normal = glm::vec3(-dx, -dy, 1.0f);
      receivers.push_back(r);
      texels_.push_back(static_cast<std::size_t>(y) * f.width + x);
    }
  // The reference scene: the field, the ground plane (the method's clamped horizon), the sky.
  reference::SceneDesc d;
  reference::HeightFieldInstance hf;
  hf.field = f;
  for (float& h : hf.field.heights) h *= hs;
  const float lo = *std::min_element(hf.field.heights.begin(), hf.field.heights.end());
  const float sx = (f.width - 1) * cs, sy = (f.height - 1) * cs;
  const float half = 500.0f * std::max(sx, sy), cx = 0.5f * sx, cy = 0.5f * sy;
  reference::MeshInstance ground;
  ground.mesh.name = "ground plane";
  ground.mesh.positions = {{cx - half, cy - half, lo},
                           {cx + half, cy - half, lo},
                           {cx + half, cy + half, lo},
                           {cx - half, cy + half, lo}};
  ground.mesh.indices = {0, 1, 2, 0, 2, 3};
  d.meshes.push_back(std::move(ground));
  float size = std::max(sx, sy);
  for (float h : hf.field.heights) size = std::max(size, std::fabs(h));
  d.height_fields.push_back(std::move(hf));
  d.environment = reference::EnvironmentLight{scene.environment, scene.rotation_rad()};
  const reference::Scene traced(d);
  reference::IrradianceOptions io;
  io.samples = options.reference_samples;
  io.seed = options.seed;
  io.ray_offset = 1e-5f * size;  // the field's own size, not the plane's
  for (const reference::RgbEstimate& r : reference::environment_irradiance(traced, receivers, io))
    reference_.push_back(r.mean);
}

settings::TerrainTuning TerrainTuner::tuning(const Config& c) const {
  settings::TerrainTuning t;
  const std::string& h = knobs_[0].values[static_cast<std::size_t>(c[0])];
  t.horizon = h == "sweep" ? "sweep" : "march";
  t.level_step = h == "march_ls2" ? 2 : 4;
  t.azimuths = std::stoi(knobs_[1].values[static_cast<std::size_t>(c[1])]);
  t.bands = std::stoi(knobs_[2].values[static_cast<std::size_t>(c[2])]);
  return t;
}

Evaluation TerrainTuner::evaluate(const settings::TerrainTuning& t) const {
  switch (t.bands) {
    case 3:
      return run_terrain<3>(scene_, sky_, t, options_, texels_, reference_);
    case 4:
      return run_terrain<4>(scene_, sky_, t, options_, texels_, reference_);
    case 5:
      return run_terrain<5>(scene_, sky_, t, options_, texels_, reference_);
    case 6:
      return run_terrain<6>(scene_, sky_, t, options_, texels_, reference_);
    default:
      throw std::invalid_argument("terrain: bands must be 3..6, got " + std::to_string(t.bands));
  }
}

}  // namespace penumbra::tune
