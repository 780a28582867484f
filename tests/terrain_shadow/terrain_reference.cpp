#include "terrain_reference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/procedural.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/terrain_shadow/transfer.h"

namespace penumbra::terrain_reference {

std::filesystem::path shared_data() {
  return PENUMBRA_SHARED_DATA;
}

namespace {

// Bilinear resampling of the central square of `f` to size x size samples.
data::HeightField resample_square(const data::HeightField& f, int size) {
  const int side = std::min(f.width, f.height);
  const int x0 = (f.width - side) / 2, y0 = (f.height - side) / 2;
  data::HeightField out;
  out.width = out.height = size;
  out.cell_size = f.cell_size * static_cast<float>(side - 1) / static_cast<float>(size - 1);
  out.heights.resize(static_cast<std::size_t>(size) * size);
  const double step = static_cast<double>(side - 1) / (size - 1);
  for (int y = 0; y < size; ++y) {
    const double v = y * step;
    const int iy = std::min(static_cast<int>(v), side - 2);
    const float fy = static_cast<float>(v - iy);
    for (int x = 0; x < size; ++x) {
      const double u = x * step;
      const int ix = std::min(static_cast<int>(u), side - 2);
      const float fx = static_cast<float>(u - ix);
      const float a = f.at(x0 + ix, y0 + iy), b = f.at(x0 + ix + 1, y0 + iy);
      const float c = f.at(x0 + ix, y0 + iy + 1), d = f.at(x0 + ix + 1, y0 + iy + 1);
      out.at(x, y) = (a + fx * (b - a)) + fy * ((c + fx * (d - c)) - (a + fx * (b - a)));
    }
  }
  out.source = f.source + " (central " + std::to_string(side) + "^2 resampled to " +
               std::to_string(size) + "^2)";
  return out;
}

// 1e-5 x the field's size (estimators.h "Ray offsets", without the ground plane's extent).
float ray_offset_for(const data::HeightField& field, float height_scale) {
  float size = static_cast<float>(std::max(field.width, field.height)) * field.cell_size;
  for (float h : field.heights) size = std::max(size, std::fabs(height_scale * h));
  return 1e-5f * size;
}

float length2(const glm::vec3& v) {
  return v.x * v.x + v.y * v.y + v.z * v.z;
}

}  // namespace

std::shared_ptr<const data::HeightField> load_terrain(std::string_view name, int size) {
  if (size < 2) throw std::invalid_argument("load_terrain: size must be >= 2");
  if (name == "dem") {
    const data::HeightField dem =
        assets::load_height_field(shared_data() / "terrain" / "jacksboro_fault_dem.pgm");
    if (size <= std::min(dem.width, dem.height))
      return std::make_shared<data::HeightField>(
          data::crop(dem, (dem.width - size) / 2, (dem.height - size) / 2, size, size));
    return std::make_shared<data::HeightField>(resample_square(dem, size));
  }
  for (std::string_view known : {"mountains", "cones", "sine_grating", "egg_tray", "city"})
    if (name == known)
      return std::make_shared<data::HeightField>(
          assets::procedural_scene(name, {size, kProceduralExtent}, 1));
  throw std::invalid_argument("load_terrain: unknown scene \"" + std::string(name) + "\"");
}

data::EnvironmentMap load_hdri(std::string_view name) {
  return assets::load_environment_map(shared_data() / "hdri" / (std::string(name) + ".exr"));
}

data::EnvironmentMap constant_environment(glm::vec3 radiance, int width, int height) {
  data::EnvironmentMap m;
  m.width = width;
  m.height = height;
  m.source = "constant";
  m.rgb.resize(3 * static_cast<std::size_t>(width) * height);
  for (std::size_t i = 0; i < m.rgb.size(); i += 3) {
    m.rgb[i] = radiance.x;
    m.rgb[i + 1] = radiance.y;
    m.rgb[i + 2] = radiance.z;
  }
  return m;
}

template <int N>
sh::CoeffsRgb<N> environment_sh(const data::EnvironmentMap& map, float rotation_z) {
  sh::CoeffsRgb<N> l = sh::project_equirect<N>(map.rgb.data(), map.width, map.height);
  for (auto& c : l) c = sh::rotate_z<N>(c, rotation_z);
  return l;
}

ReceiverSet texel_receivers(const data::HeightField& field, float height_scale,
                            std::span<const glm::ivec2> texels) {
  ReceiverSet out;
  out.width = field.width;
  out.height = field.height;
  const float cs = field.cell_size;
  for (const glm::ivec2& t : texels) {
    const int x = t.x, y = t.y;
    if (x < 0 || y < 0 || x >= field.width || y >= field.height)
      throw std::invalid_argument("texel_receivers: texel (" + std::to_string(x) + ", " +
                                  std::to_string(y) + ") is outside " + field.source);
    // Central differences, one-sided at the border: TerrainShadowing::compute_normals and
    // reference::height_field_receivers, term for term.
    const int xa = std::max(x - 1, 0), xb = std::min(x + 1, field.width - 1);
    const int ya = std::max(y - 1, 0), yb = std::min(y + 1, field.height - 1);
    const float dx = height_scale * (field.at(xb, y) - field.at(xa, y)) / ((xb - xa) * cs);
    const float dy = height_scale * (field.at(x, yb) - field.at(x, ya)) / ((yb - ya) * cs);
    const glm::vec3 n(-dx, -dy, 1.0f);
    reference::Receiver r;
    r.position = {x * cs, y * cs, height_scale * field.at(x, y)};
    r.normal = n / std::sqrt(length2(n));
    out.texels.push_back(static_cast<std::size_t>(y) * field.width + x);
    out.receivers.push_back(r);
  }
  return out;
}

ReceiverSet texel_receivers(const data::HeightField& field, float height_scale, int stride) {
  if (stride < 1) throw std::invalid_argument("texel_receivers: stride must be >= 1");
  std::vector<glm::ivec2> texels;
  for (int y = stride / 2; y < field.height; y += stride)
    for (int x = stride / 2; x < field.width; x += stride) texels.emplace_back(x, y);
  return texel_receivers(field, height_scale, texels);
}

reference::SceneDesc reference_scene(const data::HeightField& field, float height_scale,
                                     const Lighting& lighting, const ReferenceOptions& options) {
  reference::SceneDesc d;
  reference::HeightFieldInstance hf;
  hf.field = field;
  for (float& h : hf.field.heights) h *= height_scale;
  if (options.ground_plane) {
    const auto lo = std::min_element(hf.field.heights.begin(), hf.field.heights.end());
    const float sx = (field.width - 1) * field.cell_size, sy = (field.height - 1) * field.cell_size;
    const float half = 0.5f * options.ground_extent * std::max(sx, sy);
    const float cx = 0.5f * sx, cy = 0.5f * sy, z = *lo;
    reference::MeshInstance ground;
    ground.mesh.name = "ground plane";
    ground.mesh.positions = {{cx - half, cy - half, z},
                             {cx + half, cy - half, z},
                             {cx + half, cy + half, z},
                             {cx - half, cy + half, z}};
    ground.mesh.indices = {0, 1, 2, 0, 2, 3};
    d.meshes.push_back(std::move(ground));
  }
  d.height_fields.push_back(std::move(hf));
  if (lighting.environment)
    d.environment = reference::EnvironmentLight{*lighting.environment, lighting.rotation_z};
  d.lights = lighting.lights;
  return d;
}

ReferenceIrradiance reference_irradiance(const data::HeightField& field, float height_scale,
                                         const ReceiverSet& receivers, const Lighting& lighting,
                                         const ReferenceOptions& options) {
  const reference::Scene scene(reference_scene(field, height_scale, lighting, options));
  // The integrator's automatic offset is relative to the scene's extent, which the ground
  // plane would inflate 1000-fold: use the field's own size instead.
  const float offset = ray_offset_for(field, height_scale);
  ReferenceIrradiance out;
  out.texels = receivers.texels;
  if (lighting.environment) {
    reference::IrradianceOptions o;
    o.samples = options.samples;
    o.seed = options.seed;
    o.ray_offset = offset;
    out.environment = reference::environment_irradiance(scene, receivers.receivers, o);
  }
  if (!lighting.lights.empty()) {
    reference::LightOptions o;
    o.samples = options.samples;
    o.seed = options.seed;
    o.ray_offset = offset;
    out.lights = reference::light_irradiance(scene, receivers.receivers, o);
  }
  return out;
}

template <int N>
ReferenceVisibility<N> reference_visibility(const data::HeightField& field, float height_scale,
                                            const ReceiverSet& receivers,
                                            const ReferenceOptions& options) {
  const reference::Scene scene(reference_scene(field, height_scale, Lighting{}, options));
  reference::VisibilityOptions o;
  o.samples = std::max(options.samples / 2, 2);
  o.ray_offset = ray_offset_for(field, height_scale);
  o.domain = reference::VisibilityDomain::kSphere;
  ReferenceVisibility<N> out;
  out.texels = receivers.texels;
  out.receivers = receivers.receivers;
  for (int k = 0; k < 2; ++k) {
    o.seed = options.seed + static_cast<std::uint64_t>(k);
    const std::vector<reference::ShEstimate<N>> v =
        reference::visibility_sh<N>(scene, receivers.receivers, o);
    out.half[k].reserve(v.size());
    for (const auto& e : v) out.half[k].push_back(e.mean);
  }
  return out;
}

namespace {

// E for each half with per-receiver SH radiance `radiance_at(i)`.
template <int N, class F>
std::vector<reference::RgbEstimate> shade_halves(const ReferenceVisibility<N>& v, F&& radiance_at) {
  std::vector<reference::RgbEstimate> out(v.receivers.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const sh::CoeffsRgb<N> l = radiance_at(i);
    glm::vec3 e[2];
    for (int k = 0; k < 2; ++k) {
      const sh::Coeffs<N> t =
          terrain_shadow::diffuse_transfer<N>(v.half[k][i], v.receivers[i].normal);
      e[k] = {sh::dot<N>(l[0], t), sh::dot<N>(l[1], t), sh::dot<N>(l[2], t)};
    }
    out[i].mean = 0.5f * (e[0] + e[1]);
    out[i].std_error = 0.5f * glm::abs(e[0] - e[1]);
    out[i].dof = 1;
  }
  return out;
}

}  // namespace

template <int N>
std::vector<reference::RgbEstimate> shade_visibility(const ReferenceVisibility<N>& v,
                                                     const sh::CoeffsRgb<N>& radiance) {
  return shade_halves(v, [&](std::size_t) { return radiance; });
}

template <int N>
std::vector<reference::RgbEstimate> shade_visibility(const ReferenceVisibility<N>& v,
                                                     const reference::SphereLight& light) {
  return shade_halves(v, [&](std::size_t i) {
    const sh::Coeffs<N> cap = terrain_shadow::spherical_light_radiance<N>(
        light.center - v.receivers[i].position, light.radius);
    sh::CoeffsRgb<N> l;
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < N * N; ++j) l[c][j] = light.radiance[c] * cap[j];
    return l;
  });
}

ErrorSummary compare(std::span<const glm::vec3> method, std::span<const std::size_t> texels,
                     std::span<const reference::RgbEstimate> reference) {
  if (texels.size() != reference.size() || texels.empty())
    throw std::invalid_argument("compare: one reference estimate per texel needed");
  ErrorSummary e;
  e.receivers = texels.size();
  double sum_ref = 0, sum_ref2 = 0, sum_err2 = 0, sum_se2 = 0, sum_signed = 0, sum_ref_c = 0;
  double max_err = 0, max_se = 0;
  for (std::size_t i = 0; i < texels.size(); ++i) {
    if (texels[i] >= method.size()) throw std::invalid_argument("compare: texel out of range");
    const glm::vec3 m = method[texels[i]], r = reference[i].mean, se = reference[i].std_error;
    const glm::vec3 d = m - r;
    const double err = std::sqrt(static_cast<double>(length2(d)));
    sum_ref += std::sqrt(static_cast<double>(length2(r)));
    sum_ref2 += length2(r);
    sum_err2 += length2(d);
    sum_se2 += length2(se);
    sum_signed += static_cast<double>(d.x) + d.y + d.z;
    sum_ref_c += static_cast<double>(r.x) + r.y + r.z;
    if (err > max_err || i == 0) {
      max_err = err;
      e.worst_texel = texels[i];
    }
    max_se = std::max(max_se, std::sqrt(static_cast<double>(length2(se))));
    if (reference[i].dof > 0)
      e.min_dof = e.min_dof == 0 ? reference[i].dof : std::min(e.min_dof, reference[i].dof);
  }
  const double n = static_cast<double>(texels.size());
  e.mean_reference = sum_ref / n;
  const double rms_ref = std::sqrt(sum_ref2 / n);
  // x / 0: +infinity for x > 0, 0 for x == 0 (see the header).
  auto ratio = [](double x, double y) {
    return y > 0 ? x / y : x > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  };
  e.rel_rms = ratio(std::sqrt(sum_err2 / n), rms_ref);
  e.ref_rel_se = ratio(std::sqrt(sum_se2 / n), rms_ref);
  e.max_rel = ratio(max_err, e.mean_reference);
  e.ref_max_se = ratio(max_se, e.mean_reference);
  e.bias = sum_ref_c > 0     ? sum_signed / sum_ref_c
           : sum_signed != 0 ? std::copysign(std::numeric_limits<double>::infinity(), sum_signed)
                             : 0.0;
  return e;
}

std::string format(const ErrorSummary& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "rel_rms %6.2f%% max_rel %6.2f%% bias %+6.2f%% (ref se %.2f%%/%.2f%%, n %zu)",
                100 * e.rel_rms, 100 * e.max_rel, 100 * e.bias, 100 * e.ref_rel_se,
                100 * e.ref_max_se, e.receivers);
  return buf;
}

std::string describe(const terrain_shadow::TerrainShadowConfig& c) {
  std::string s = terrain_shadow::to_string(c.method);
  if (c.method == terrain_shadow::HorizonMethod::kMarch) {
    char buf[48];
    std::snprintf(buf, sizeof buf, " ls%d lo%g", c.pyramid.level_step, c.march.level_offset);
    s += buf;
  }
  return s + " n" + std::to_string(c.azimuths);
}

template <int N>
std::vector<glm::vec3> method_environment(const terrain_shadow::TerrainShadowConfig& config,
                                          std::shared_ptr<const data::HeightField> field,
                                          float height_scale, const sh::CoeffsRgb<N>& radiance) {
  terrain_shadow::TerrainShadowing<N> ts(config);
  ts.update(std::move(field), height_scale);
  std::vector<glm::vec3> e;
  ts.shade_environment(radiance, e);
  return e;
}

template sh::CoeffsRgb<3> environment_sh<3>(const data::EnvironmentMap&, float);
template sh::CoeffsRgb<4> environment_sh<4>(const data::EnvironmentMap&, float);
template sh::CoeffsRgb<5> environment_sh<5>(const data::EnvironmentMap&, float);
template sh::CoeffsRgb<6> environment_sh<6>(const data::EnvironmentMap&, float);
#define PENUMBRA_VIS_INSTANTIATE(N)                                                               \
  template ReferenceVisibility<N> reference_visibility<N>(                                        \
      const data::HeightField&, float, const ReceiverSet&, const ReferenceOptions&);              \
  template std::vector<reference::RgbEstimate> shade_visibility<N>(const ReferenceVisibility<N>&, \
                                                                   const sh::CoeffsRgb<N>&);      \
  template std::vector<reference::RgbEstimate> shade_visibility<N>(const ReferenceVisibility<N>&, \
                                                                   const reference::SphereLight&);
PENUMBRA_VIS_INSTANTIATE(3)
PENUMBRA_VIS_INSTANTIATE(4)
PENUMBRA_VIS_INSTANTIATE(5)
#undef PENUMBRA_VIS_INSTANTIATE
template std::vector<glm::vec3> method_environment<3>(const terrain_shadow::TerrainShadowConfig&,
                                                      std::shared_ptr<const data::HeightField>,
                                                      float, const sh::CoeffsRgb<3>&);
template std::vector<glm::vec3> method_environment<4>(const terrain_shadow::TerrainShadowConfig&,
                                                      std::shared_ptr<const data::HeightField>,
                                                      float, const sh::CoeffsRgb<4>&);
template std::vector<glm::vec3> method_environment<5>(const terrain_shadow::TerrainShadowConfig&,
                                                      std::shared_ptr<const data::HeightField>,
                                                      float, const sh::CoeffsRgb<5>&);

}  // namespace penumbra::terrain_reference
