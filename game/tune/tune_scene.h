// Tune scenes (scenes/tune_*.json; `./penumbra tune SCENE`, docs/tune.md): a terrain crop of a
// height map, an HDR sky, and objects (glTF models, fitted with sphere sets for the blockers),
// plus the probe volume. The probe bake's scene format (bake_scene.h) has no objects with sphere
// sets or receiver settings and rejects unknown fields, so tune scenes have their own small
// format; bake_scene_json() turns one into a bake scene for the probe bake.
//
// Format (every field checked; unknown fields are errors; numbers finite):
//   {"name": str, "comment": str (optional),
//    "terrain": {"file": path, "crop": [x0, y0, w, h], "cell_size": m, "height_scale": s,
//                "albedo": [r, g, b], "stride": texels between receivers},
//    "environment": {"file": path, "rotation_deg": deg},
//    "objects": [{"model": path, "position": [x, y], "size": m, "lift": m, "rotation_deg": deg,
//                 "albedo": [r, g, b]}, ...],
//    "probes": {"min": [x, y, z], "max": [x, y, z], "points": n}}
// Paths are relative to the data directory (../shared/data). The terrain's sample (0, 0) lies
// at the origin (as TerrainShadowing places it); heights are file value x height_scale. An
// object's model (merge_instances: z up) is scaled so its largest extent is `size`, turned
// about +z, and set with its lowest point `lift` metres above the terrain sample nearest
// `position`. The probe volume's `points` are the free points the probes' error is measured at.
// Errors: std::runtime_error "<scene file>: <field path>: <reason>"; the loaders' own errors
// (assets::LoadError naming the data file) come through unchanged.
// Threading: plain data after loading.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"

namespace penumbra::tune {

struct TuneObject {
  std::string model;         // path relative to the data directory
  glm::mat4 world{1.0f};     // engine model frame -> world
  float scale = 1;           // uniform scale inside `world`
  glm::vec3 translation{0};  // inside `world`
  float rotation_deg = 0;    // inside `world`
  glm::vec3 albedo{0.5f};
  data::MeshData local;    // merge_instances(model): the model's own frame, z up
  data::MeshData mesh;     // in world space
  glm::vec3 ground{0.0f};  // the terrain point under the object's position
  float radius = 0;        // horizontal radius of the world mesh around `ground`
};

struct TuneScene {
  std::string name;
  std::string source;  // the scene file, for messages
  std::filesystem::path data_dir;
  // Terrain
  std::string terrain_file;
  std::array<int, 4> crop{};
  float cell_size = 1, height_scale = 1;
  glm::vec3 terrain_albedo{0.3f};
  int stride = 4;
  std::shared_ptr<const data::HeightField> field;  // heights as in the file (not scaled)
  // Sky
  std::string environment_file;
  float rotation_deg = 0;
  data::EnvironmentMap environment;
  // Objects
  std::vector<TuneObject> objects;
  // Probes
  glm::vec3 probe_min{0.0f}, probe_max{0.0f};
  int probe_points = 64;

  float rotation_rad() const;
  // The field's horizontal extent (metres, the longer side).
  float extent() const;
  // Scaled height at the sample nearest (x, y) (clamped to the field).
  float ground_height(float x, float y) const;
};

TuneScene load_tune_scene(const std::filesystem::path& file, const std::filesystem::path& data_dir);
TuneScene parse_tune_scene(const std::string& json, const std::string& name,
                           const std::filesystem::path& data_dir);

// The scene as a probe bake scene (bake_scene.h): the terrain as a height field, the objects as
// glTF geometry, the sky, and the probe volume at `spacing` metres.
std::string bake_scene_json(const TuneScene& scene, float spacing);

}  // namespace penumbra::tune
