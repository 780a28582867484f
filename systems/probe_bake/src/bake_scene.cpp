// Bake scene loader (bake_scene.h): nlohmann-json with every field checked by path.
#include "penumbra/systems/probe_bake/bake_scene.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "penumbra/assets/exr.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/heightmap.h"
#include "penumbra/assets/json_fields.h"
#include "penumbra/assets/sphere_fit.h"

namespace penumbra::probe_bake {
namespace {

using Json = nlohmann::json;

// The bake scene's fields (engine/assets/internal json_fields.h), with its own albedo rule:
// optional, black when absent.
class Reader : public assets::JsonFields {
 public:
  using JsonFields::JsonFields;
  glm::vec3 albedo(const Json& j, const std::string& path) const {
    if (!j.contains("albedo")) return glm::vec3(0.0f);
    const glm::vec3 a = vec3(j, path, "albedo");
    for (int i = 0; i < 3; ++i)
      if (a[i] < 0 || a[i] > 1) fail(path + ".albedo", "each channel must be in [0, 1]");
    return a;
  }
};

constexpr float kDeg = 3.14159265358979f / 180.0f;

void add_box(BakeScene& s, const glm::vec3& center, const glm::vec3& size, float rotation_z,
             const glm::vec3& albedo, const std::string& name) {
  const glm::mat4 m = glm::scale(
      glm::rotate(glm::translate(glm::mat4(1.0f), center), rotation_z, glm::vec3(0, 0, 1)), size);
  reference::MeshInstance inst{unit_box_mesh(), m, albedo};
  inst.mesh.name = name;
  s.desc.meshes.push_back(std::move(inst));
  Solid solid;
  solid.kind = Solid::Kind::kBox;
  solid.world_to_unit = glm::inverse(m);
  s.solids.push_back(solid);
}

// A wall from a to b (x-y), thickness t, z in [z0, z1].
void add_wall(BakeScene& s, glm::vec2 a, glm::vec2 b, float z0, float z1, float t,
              const glm::vec3& albedo, const std::string& name) {
  const glm::vec2 d = b - a;
  const float len = glm::length(d);
  const glm::vec2 c = 0.5f * (a + b);
  add_box(s, glm::vec3(c, 0.5f * (z0 + z1)), glm::vec3(len, t, z1 - z0), std::atan2(d.y, d.x),
          albedo, name);
}

void add_geometry(BakeScene& s, const Reader& r, const Json& g, const std::string& path,
                  const std::filesystem::path& data_dir) {
  if (!g.is_object()) r.fail(path, std::string("expected an object, got ") + g.type_name());
  const std::string kind = r.string(g, path, "kind");
  const std::string name = g.contains("name") ? r.string(g, path, "name") : path;
  const glm::vec3 albedo = r.albedo(g, path);
  if (kind == "box") {
    r.only(g, path, {"kind", "name", "albedo", "center", "size", "rotation_deg"});
    const glm::vec3 size = r.vec3(g, path, "size");
    if (!(size.x > 0 && size.y > 0 && size.z > 0)) r.fail(path + ".size", "must be > 0");
    add_box(s, r.vec3(g, path, "center"), size, kDeg * r.number_or(g, path, "rotation_deg", 0),
            albedo, name);
  } else if (kind == "wall" || kind == "arch") {
    std::set<std::string> allowed = {"kind", "name", "albedo", "from",
                                     "to",   "base", "height", "thickness"};
    if (kind == "arch") allowed.insert({"opening_width", "opening_height"});
    r.only(g, path, allowed);
    const auto f = r.vec<2>(g, path, "from"), t = r.vec<2>(g, path, "to");
    const glm::vec2 a(f[0], f[1]), b(t[0], t[1]);
    if (!(glm::length(b - a) > 0)) r.fail(path + ".to", "equals from");
    const float z0 = r.number(g, path, "base"), h = r.positive(g, path, "height");
    const float th = r.positive(g, path, "thickness");
    if (kind == "wall") {
      add_wall(s, a, b, z0, z0 + h, th, albedo, name);
    } else {
      const float ow = r.positive(g, path, "opening_width");
      const float oh = r.positive(g, path, "opening_height");
      const float len = glm::length(b - a);
      if (ow >= len) r.fail(path + ".opening_width", "must be below the arch's length");
      if (oh >= h) r.fail(path + ".opening_height", "must be below its height");
      const glm::vec2 u = (b - a) / len;
      const float side = 0.5f * (len - ow);
      add_wall(s, a, a + side * u, z0, z0 + h, th, albedo, name + "/left");
      add_wall(s, b - side * u, b, z0, z0 + h, th, albedo, name + "/right");
      add_wall(s, a + side * u, b - side * u, z0 + oh, z0 + h, th, albedo, name + "/lintel");
    }
  } else if (kind == "sphere") {
    r.only(g, path, {"kind", "name", "albedo", "center", "radius"});
    reference::SphereOccluder o{r.vec3(g, path, "center"), r.positive(g, path, "radius"), name,
                                albedo};
    s.desc.spheres.push_back(o);
    Solid solid;
    solid.kind = Solid::Kind::kSphere;
    solid.center = o.center;
    solid.radius = o.radius;
    s.solids.push_back(solid);
  } else if (kind == "heightfield") {
    r.only(g, path,
           {"kind", "name", "albedo", "file", "crop", "cell_size", "height_scale", "origin"});
    data::HeightField f = assets::load_height_field(data_dir / r.string(g, path, "file"));
    if (g.contains("crop")) {
      const auto c = r.vec<4>(g, path, "crop");
      f = data::crop(f, static_cast<int>(c[0]), static_cast<int>(c[1]), static_cast<int>(c[2]),
                     static_cast<int>(c[3]));
    }
    if (g.contains("cell_size")) f.cell_size = r.positive(g, path, "cell_size");
    const float scale = r.number_or(g, path, "height_scale", 1.0f);
    for (float& v : f.heights) v *= scale;
    reference::HeightFieldInstance inst{std::move(f), r.vec3(g, path, "origin"), albedo};
    s.desc.height_fields.push_back(std::move(inst));
    Solid solid;
    solid.kind = Solid::Kind::kHeightField;
    solid.height_field = static_cast<int>(s.desc.height_fields.size() - 1);
    s.solids.push_back(solid);
  } else if (kind == "gltf") {
    r.only(g, path, {"kind", "name", "albedo", "file", "translation", "scale", "rotation_deg"});
    const assets::Model model = assets::load_gltf(data_dir / r.string(g, path, "file"));
    const glm::mat4 m =
        glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), r.vec3(g, path, "translation")),
                               kDeg * r.number_or(g, path, "rotation_deg", 0), glm::vec3(0, 0, 1)),
                   glm::vec3(g.contains("scale") ? r.positive(g, path, "scale") : 1.0f));
    reference::MeshInstance inst{assets::merge_instances(model), m, albedo};
    inst.mesh.name = name;
    const MeshClosure closure = mesh_closure(inst.mesh);
    if (closure.closed()) {
      Solid solid;
      solid.kind = Solid::Kind::kMesh;
      solid.mesh = std::make_shared<const SolidMesh>(inst.mesh, m);
      s.solids.push_back(solid);
    } else {
      s.notes.push_back(path + " (" + r.string(g, path, "file") + "): open mesh (" +
                        std::to_string(closure.boundary_edges) + " boundary, " +
                        std::to_string(closure.nonmanifold_edges) +
                        " non-manifold edges): no inside, probes in it are not found invalid");
    }
    s.desc.meshes.push_back(std::move(inst));
  } else {
    r.fail(path + ".kind",
           "unknown geometry kind \"" + kind + "\" (box, wall, arch, sphere, heightfield, gltf)");
  }
}

}  // namespace

data::MeshData unit_box_mesh() {
  data::MeshData m;
  m.name = "box";
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f,
                             (i & 4) ? 0.5f : -0.5f);
  // Outward winding (counter-clockwise seen from outside).
  m.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
               2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return m;
}

bool BakeScene::inside(const glm::vec3& p) const {
  for (const Solid& s : solids) {
    switch (s.kind) {
      case Solid::Kind::kBox: {
        const glm::vec4 q = s.world_to_unit * glm::vec4(p, 1.0f);
        if (std::fabs(q.x) < 0.5f && std::fabs(q.y) < 0.5f && std::fabs(q.z) < 0.5f) return true;
        break;
      }
      case Solid::Kind::kSphere: {
        const glm::vec3 d = p - s.center;
        if (glm::dot(d, d) < s.radius * s.radius) return true;
        break;
      }
      case Solid::Kind::kHeightField: {
        const reference::HeightFieldInstance& h =
            desc.height_fields[static_cast<std::size_t>(s.height_field)];
        const data::HeightField& f = h.field;
        const float gx = (p.x - h.origin.x) / f.cell_size, gy = (p.y - h.origin.y) / f.cell_size;
        if (!(gx >= 0 && gy >= 0 && gx <= f.width - 1 && gy <= f.height - 1)) break;
        const int x = std::min(static_cast<int>(gx), f.width - 2);
        const int y = std::min(static_cast<int>(gy), f.height - 2);
        const float fx = gx - x, fy = gy - y;
        const float h00 = f.at(x, y), h10 = f.at(x + 1, y), h01 = f.at(x, y + 1),
                    h11 = f.at(x + 1, y + 1);
        // The two triangles of scene.h: split along (x, y)-(x+1, y+1).
        const float z = fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10)
                                 : h00 + fy * (h01 - h00) + fx * (h11 - h01);
        if (p.z < h.origin.z + z) return true;
        break;
      }
      case Solid::Kind::kMesh:
        if (s.mesh && s.mesh->inside(p)) return true;
        break;
    }
  }
  return false;
}

BakeScene parse_bake_scene(std::string_view json, const std::string& name,
                           const std::filesystem::path& data_dir) {
  const Reader r(name);
  Json j;
  try {
    j = Json::parse(json.begin(), json.end());
  } catch (const Json::exception& e) {  // parse_error, out_of_range (1e999)
    throw std::runtime_error(
        name + ": not valid JSON (NaN and Infinity are not JSON numbers): " + e.what());
  }
  r.only(j, "(top)", {"name", "environment", "geometry", "lights", "probes", "comment"});
  BakeScene s;
  s.source = name;
  s.name = j.contains("name") ? r.string(j, "(top)", "name") : name;
  if (j.contains("environment")) {
    const Json& e = j["environment"];
    r.only(e, "environment", {"file", "rotation_deg", "scale"});
    data::EnvironmentMap map =
        assets::load_environment_map(data_dir / r.string(e, "environment", "file"));
    const float scale = r.number_or(e, "environment", "scale", 1.0f);
    if (scale < 0) r.fail("environment.scale", "must be >= 0");
    for (float& v : map.rgb) v *= scale;
    s.desc.environment = reference::EnvironmentLight{
        std::move(map), kDeg * r.number_or(e, "environment", "rotation_deg", 0)};
  }
  if (j.contains("geometry")) {
    const Json& g = j["geometry"];
    if (!g.is_array()) r.fail("geometry", std::string("expected an array, got ") + g.type_name());
    for (std::size_t i = 0; i < g.size(); ++i)
      add_geometry(s, r, g[i], "geometry[" + std::to_string(i) + "]", data_dir);
  }
  if (j.contains("lights")) {
    const Json& l = j["lights"];
    if (!l.is_array()) r.fail("lights", std::string("expected an array, got ") + l.type_name());
    for (std::size_t i = 0; i < l.size(); ++i) {
      const std::string path = "lights[" + std::to_string(i) + "]";
      r.only(l[i], path, {"name", "center", "radius", "radiance"});
      reference::SphereLight light;
      light.name = l[i].contains("name") ? r.string(l[i], path, "name") : path;
      light.center = r.vec3(l[i], path, "center");
      light.radius = r.positive(l[i], path, "radius");
      light.radiance = r.vec3(l[i], path, "radiance");
      if (light.radiance.x < 0 || light.radiance.y < 0 || light.radiance.z < 0)
        r.fail(path + ".radiance", "must be >= 0");
      s.desc.lights.push_back(light);
    }
  }
  const Json& p = r.field(j, "(top)", "probes");
  r.only(p, "probes", {"min", "max", "spacing"});
  s.volume.min = r.vec3(p, "probes", "min");
  s.volume.max = r.vec3(p, "probes", "max");
  s.volume.spacing = r.positive(p, "probes", "spacing");
  for (int k = 0; k < 3; ++k)
    if (!(s.volume.max[k] >= s.volume.min[k])) r.fail("probes.max", "below probes.min");
  return s;
}

BakeScene load_bake_scene(const std::filesystem::path& file,
                          const std::filesystem::path& data_dir) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_bake_scene(ss.str(), file.string(), data_dir);
}

}  // namespace penumbra::probe_bake
