#include "tune_scene.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/json_fields.h"
#include "penumbra/assets/sphere_fit.h"

namespace penumbra::tune {

namespace {

using Json = nlohmann::json;
constexpr float kDeg = 3.14159265358979f / 180.0f;

// The tune scene's fields (engine/assets/internal json_fields.h), with its own albedo rule:
// required.
class Reader : public assets::JsonFields {
 public:
  using JsonFields::JsonFields;
  glm::vec3 albedo(const Json& j, const std::string& path) const {
    const glm::vec3 a = vec3(j, path, "albedo");
    for (int k = 0; k < 3; ++k)
      if (!(a[k] >= 0 && a[k] <= 1)) fail(path + ".albedo", "components must lie in [0, 1]");
    return a;
  }
};

}  // namespace

float TuneScene::rotation_rad() const {
  return rotation_deg * kDeg;
}

float TuneScene::extent() const {
  return static_cast<float>(std::max(field->width, field->height) - 1) * field->cell_size;
}

float TuneScene::ground_height(float x, float y) const {
  const int ix =
      std::clamp(static_cast<int>(std::lround(x / field->cell_size)), 0, field->width - 1);
  const int iy =
      std::clamp(static_cast<int>(std::lround(y / field->cell_size)), 0, field->height - 1);
  return height_scale * field->at(ix, iy);
}

TuneScene parse_tune_scene(const std::string& json, const std::string& name,
                           const std::filesystem::path& data_dir) {
  const Reader r{name};
  Json j;
  try {
    j = Json::parse(json);
  } catch (const Json::exception& e) {
    throw std::runtime_error(name + ": not JSON: " + e.what());
  }
  r.only(j, "scene", {"name", "comment", "terrain", "environment", "objects", "probes"});
  TuneScene s;
  s.source = name;
  s.data_dir = data_dir;
  s.name = r.string(j, "scene", "name");

  const Json& t = r.field(j, "scene", "terrain");
  r.only(t, "terrain", {"file", "crop", "cell_size", "height_scale", "albedo", "stride"});
  s.terrain_file = r.string(t, "terrain", "file");
  const auto crop = r.vec<4>(t, "terrain", "crop");
  for (int k = 0; k < 4; ++k) s.crop[k] = static_cast<int>(crop[k]);
  if (s.crop[2] < 8 || s.crop[3] < 8) r.fail("terrain.crop", "at least 8 x 8 samples");
  s.cell_size = r.positive(t, "terrain", "cell_size");
  s.height_scale = r.positive(t, "terrain", "height_scale");
  s.terrain_albedo = r.albedo(t, "terrain");
  s.stride = r.integer(t, "terrain", "stride", 1, 64);
  {
    data::HeightField f = assets::load_height_field(data_dir / s.terrain_file);
    f = data::crop(f, s.crop[0], s.crop[1], s.crop[2], s.crop[3]);
    if (f.width != s.crop[2] || f.height != s.crop[3])
      r.fail("terrain.crop", "outside " + s.terrain_file);
    f.cell_size = s.cell_size;
    s.field = std::make_shared<const data::HeightField>(std::move(f));
  }

  const Json& e = r.field(j, "scene", "environment");
  r.only(e, "environment", {"file", "rotation_deg"});
  s.environment_file = r.string(e, "environment", "file");
  s.rotation_deg = r.number(e, "environment", "rotation_deg");
  s.environment = assets::load_environment_map(data_dir / s.environment_file);

  const Json& objects = r.field(j, "scene", "objects");
  if (!objects.is_array()) r.fail("objects", "expected an array");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string p = "objects[" + std::to_string(i) + "]";
    const Json& o = objects[i];
    r.only(o, p, {"model", "position", "size", "lift", "rotation_deg", "albedo"});
    TuneObject obj;
    obj.model = r.string(o, p, "model");
    const auto pos = r.vec<2>(o, p, "position");
    const float size = r.positive(o, p, "size");
    const float lift = r.number(o, p, "lift");
    if (lift < 0) r.fail(p + ".lift", "must be >= 0");
    obj.rotation_deg = r.number(o, p, "rotation_deg");
    obj.albedo = r.albedo(o, p);
    obj.local = assets::merge_instances(assets::load_gltf(data_dir / obj.model));
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& v : obj.local.positions) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    const glm::vec3 ext = hi - lo;
    obj.scale = size / std::max({ext.x, ext.y, ext.z});
    const float rot = obj.rotation_deg * kDeg;
    const glm::vec3 c(0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), lo.z);
    const glm::vec3 rc(std::cos(rot) * c.x - std::sin(rot) * c.y,
                       std::sin(rot) * c.x + std::cos(rot) * c.y, c.z);
    obj.ground = {pos[0], pos[1], s.ground_height(pos[0], pos[1])};
    obj.translation = obj.ground + glm::vec3(0, 0, lift) - obj.scale * rc;
    // As bake_scene.cpp composes a glTF entry: translate, rotate about +z, scale.
    obj.world = glm::scale(
        glm::rotate(glm::translate(glm::mat4(1.0f), obj.translation), rot, glm::vec3(0, 0, 1)),
        glm::vec3(obj.scale));
    obj.mesh = obj.local;
    obj.mesh.normals.clear();
    for (glm::vec3& v : obj.mesh.positions) {
      v = glm::vec3(obj.world * glm::vec4(v, 1.0f));
      obj.radius = std::max(obj.radius, std::hypot(v.x - obj.ground.x, v.y - obj.ground.y));
    }
    s.objects.push_back(std::move(obj));
  }

  const Json& pr = r.field(j, "scene", "probes");
  r.only(pr, "probes", {"min", "max", "points"});
  s.probe_min = r.vec3(pr, "probes", "min");
  s.probe_max = r.vec3(pr, "probes", "max");
  for (int k = 0; k < 3; ++k)
    if (!(s.probe_max[k] > s.probe_min[k])) r.fail("probes", "max must exceed min on every axis");
  s.probe_points = r.integer(pr, "probes", "points", 1, 100000);
  return s;
}

TuneScene load_tune_scene(const std::filesystem::path& file,
                          const std::filesystem::path& data_dir) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot be opened");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_tune_scene(text, file.string(), data_dir);
}

std::string bake_scene_json(const TuneScene& s, float spacing) {
  auto v3 = [](glm::vec3 v) { return Json::array({v.x, v.y, v.z}); };
  Json j;
  j["name"] = s.name;
  j["environment"] = {{"file", s.environment_file}, {"rotation_deg", s.rotation_deg}};
  Json geometry = Json::array();
  geometry.push_back({{"kind", "heightfield"},
                      {"name", "terrain"},
                      {"file", s.terrain_file},
                      {"crop", Json::array({s.crop[0], s.crop[1], s.crop[2], s.crop[3]})},
                      {"cell_size", s.cell_size},
                      {"height_scale", s.height_scale},
                      {"origin", Json::array({0, 0, 0})},
                      {"albedo", v3(s.terrain_albedo)}});
  for (const TuneObject& o : s.objects)
    geometry.push_back({{"kind", "gltf"},
                        {"name", o.model},
                        {"file", o.model},
                        {"translation", v3(o.translation)},
                        {"scale", o.scale},
                        {"rotation_deg", o.rotation_deg},
                        {"albedo", v3(o.albedo)}});
  j["geometry"] = geometry;
  j["probes"] = {{"min", v3(s.probe_min)}, {"max", v3(s.probe_max)}, {"spacing", spacing}};
  return j.dump();
}

}  // namespace penumbra::tune
