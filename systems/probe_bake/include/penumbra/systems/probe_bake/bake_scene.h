// Bake scenes (issue 14): a JSON description (scenes/*.json) of the static geometry, the
// environment, the lights and the probe volume, loaded into a reference::SceneDesc for the ray
// tracer plus the solids the validity pass tests points against.
//
// Format (every field checked; numbers must be finite; unknown top-level or geometry fields are
// errors, so a typo never silently drops a wall):
//   {
//     "name": "room",
//     "environment": {"file": "hdri/sky.exr", "rotation_deg": 0, "scale": 1},   // optional
//     "geometry": [ {"kind": K, "name": "...", "albedo": [r, g, b], ...}, ... ],  // optional
//     "lights": [ {"name": "...", "center": [x, y, z], "radius": r, "radiance": [r, g, b]} ],
//     "probes": {"min": [x, y, z], "max": [x, y, z], "spacing": s}
//   }
// Geometry kinds (albedo optional, default black; name optional):
//   "box":     center [3], size [3] (full extents), rotation_deg (about +z, default 0)
//   "wall":    from [x, y], to [x, y], base (z), height, thickness: a box along the segment
//   "arch":    a wall with a centred opening: opening_width, opening_height (from the base):
//              two pillars and a lintel (three boxes)
//   "sphere":  center [3], radius
//   "heightfield": file (relative to the data dir), crop [x0, y0, w, h] (optional),
//              cell_size (optional: the file's), height_scale (default 1), origin [3]
//   "gltf":    file (relative to the data dir), translation [3], scale, rotation_deg (about +z)
// Paths (environment, height fields, glTF) are relative to the shared data directory
// (../shared/data in this project); the loaders' own errors (missing file, NaN in a mesh or
// height map) come through unchanged, naming their file.
// Solids (validity): boxes, walls, arches, spheres and height fields have an inside (below the
// surface for a height field, within its x-y extent); a glTF mesh has one when it is closed
// (solid_mesh.h). An open glTF mesh has none, so a probe inside it is never found invalid; the
// scene says so in `notes`.
// Errors: std::runtime_error "<scene file>: <field path>: <reason>", e.g.
//   "scenes/room.json: geometry[3].size[1]: expected a number, got string".
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/reference/scene.h"
#include "penumbra/systems/probe_bake/solid_mesh.h"

namespace penumbra::probe_bake {

struct Solid {
  enum class Kind { kBox, kSphere, kHeightField, kMesh };
  Kind kind = Kind::kBox;
  glm::mat4 world_to_unit{1.0f};  // box: inside when every |coordinate| < 0.5
  glm::vec3 center{0.0f};         // sphere
  float radius = 0;
  int height_field = -1;                  // index into desc.height_fields
  std::shared_ptr<const SolidMesh> mesh;  // a closed glTF mesh
};

struct ProbeVolume {
  glm::vec3 min{0.0f}, max{0.0f};
  float spacing = 1;  // metres between grid probes
};

struct BakeScene {
  std::string name;
  std::string source;  // the scene file, for messages
  reference::SceneDesc desc;
  std::vector<Solid> solids;
  ProbeVolume volume;
  std::vector<std::string> notes;  // e.g. an open glTF mesh that has no inside

  // Is p strictly inside a solid (see above)?
  bool inside(const glm::vec3& p) const;
};

// Parses a scene; `name` is the file name used in messages, `data_dir` resolves the files it
// names.
BakeScene parse_bake_scene(std::string_view json, const std::string& name,
                           const std::filesystem::path& data_dir);
BakeScene load_bake_scene(const std::filesystem::path& file, const std::filesystem::path& data_dir);

// A box mesh (12 triangles, outward winding) of unit size centred at the origin.
data::MeshData unit_box_mesh();

}  // namespace penumbra::probe_bake
