// SolidMesh and mesh_closure (solid_mesh.h): which meshes are closed, the parity inside test
// against a box's analytic inside, and a closed glTF model in a bake scene: probes inside it are
// found invalid ("a closed box with no inside" before: they kept their dark captures).
#include "penumbra/systems/probe_bake/solid_mesh.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/stability.h"
#include "penumbra/systems/probe_bake/bake_scene.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

// Debian's assimp-testmodels (a declared dependency): a 24-vertex box, each face its own copies.
const std::filesystem::path kBoxDir = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary";

// The unit box with every face's four corners copied (as glTF splits them at UV seams).
data::MeshData split_box() {
  const data::MeshData box = unit_box_mesh();
  data::MeshData m;
  for (std::size_t t = 0; t < box.indices.size(); ++t) {
    m.positions.push_back(box.positions[box.indices[t]]);
    m.indices.push_back(static_cast<std::uint32_t>(t));
  }
  return m;
}

TEST(MeshClosure, ABoxIsClosedAndItsBreakagesAreNot) {
  const MeshClosure c = mesh_closure(unit_box_mesh());
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.welded_vertices, 8u);
  EXPECT_EQ(c.edges, 18u);  // 12 box edges + 6 face diagonals
  // Seam copies weld back into the same closed box.
  const MeshClosure s = mesh_closure(split_box());
  EXPECT_TRUE(s.closed());
  EXPECT_EQ(s.welded_vertices, 8u);
  // One face (two triangles) removed: its four edges are boundary edges.
  data::MeshData open = unit_box_mesh();
  open.indices.resize(open.indices.size() - 6);
  const MeshClosure o = mesh_closure(open);
  EXPECT_FALSE(o.closed());
  EXPECT_EQ(o.boundary_edges, 4u);
  // A fin (a triangle on an existing edge): that edge has three triangles.
  data::MeshData fin = unit_box_mesh();
  fin.positions.emplace_back(0.0f, 0.0f, 3.0f);
  fin.indices.insert(fin.indices.end(), {0, 2, static_cast<std::uint32_t>(8)});
  const MeshClosure f = mesh_closure(fin);
  EXPECT_FALSE(f.closed());
  EXPECT_GE(f.nonmanifold_edges, 1u);
  // Nothing at all, or only degenerate triangles, is not closed.
  EXPECT_FALSE(mesh_closure(data::MeshData{}).closed());
  data::MeshData flat;
  flat.positions = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(1.0f)};
  flat.indices = {0, 1, 2};
  EXPECT_FALSE(mesh_closure(flat).closed());
  EXPECT_THROW(SolidMesh(open, glm::mat4(1.0f)), std::invalid_argument);
}

// A turned, scaled, moved box: the parity test agrees with the analytic inside on a grid of
// points (those within 1e-3 of a face left out), including points in line with its edges and
// vertices and on its diagonal planes.
TEST(SolidMesh, InsideAgreesWithTheBoxsOwnTest) {
  const glm::mat4 m = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), {1.0f, -2.0f, 0.5f}),
                                             0.4f, glm::vec3(0.3f, 0.2f, 1.0f)),
                                 glm::vec3(2.0f, 1.0f, 3.0f));
  const glm::mat4 to_unit = glm::inverse(m);
  for (const data::MeshData& mesh : {unit_box_mesh(), split_box()}) {
    const SolidMesh solid(mesh, m);
    int inside = 0, checked = 0;
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 16; ++j)
        for (int k = 0; k <= 16; ++k) {
          const glm::vec3 p = glm::vec3(1.0f, -2.0f, 0.5f) + glm::vec3(i - 8, j - 8, k - 8) * 0.25f;
          const glm::vec3 q = glm::vec3(to_unit * glm::vec4(p, 1.0f));
          const float margin = 0.5f - std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)});
          if (std::fabs(margin) < 1e-3f) continue;
          ++checked;
          inside += margin > 0;
          EXPECT_EQ(solid.inside(p), margin > 0) << p.x << " " << p.y << " " << p.z;
        }
    EXPECT_GT(inside, 100);
    EXPECT_GT(checked - inside, 1000);
  }
}

// A closed glTF box (assimp's BoxTextured.glb, 1 m, scaled to 3 m) over the middle of a 5^3
// grid: its 27 inner probes are invalid (offset out or dilated), none kept as captured. Without
// the box's inside (solids cleared: the behaviour before) they stay "valid" with their dark
// captures inside the model.
TEST(SolidMesh, ProbesInsideAClosedGltfModelAreInvalid) {
  PENUMBRA_STABILITY("a closed glTF model over the probe grid (27 probes inside)",
                     "the 27 are invalid (offset out or dilated), none kept with its black capture",
                     "the model's inside test");
  const std::string json = R"({
    "geometry": [{"kind": "gltf", "file": "BoxTextured.glb", "translation": [0,0,0], "scale": 3,
                  "albedo": [0.5,0.5,0.5]}],
    "lights": [{"center": [0,0,8], "radius": 1, "radiance": [20,20,20]}],
    "probes": {"min": [-2,-2,-2], "max": [2,2,2], "spacing": 1}})";
  BakeScene s = parse_bake_scene(json, "closed_box.json", kBoxDir);
  ASSERT_EQ(s.solids.size(), 1u);
  EXPECT_EQ(s.solids[0].kind, Solid::Kind::kMesh);
  EXPECT_TRUE(s.notes.empty());
  BakeSettings b;
  b.samples = 64;
  const auto inner = [](const glm::vec3& p) {
    return std::fabs(p.x) < 1.5f && std::fabs(p.y) < 1.5f && std::fabs(p.z) < 1.5f;
  };
  BakeReport r;
  bake_probe_cloud(s, b, &r);
  EXPECT_TRUE(r.valid_cloud);
  int inside = 0;
  for (const ProbeRecord& p : r.probes) {
    if (!inner(p.placed) || p.edge_round != 0) continue;
    ++inside;
    EXPECT_NE(p.state, ProbeState::kValid) << p.placed.x << " " << p.placed.y << " " << p.placed.z;
    if (p.state == ProbeState::kOffset) {
      EXPECT_FALSE(inner(p.position));
    }
  }
  EXPECT_EQ(inside, 27);

  s.solids.clear();
  BakeReport before;
  bake_probe_cloud(s, b, &before);
  int kept_dark = 0;
  for (const ProbeRecord& p : before.probes)
    kept_dark += inner(p.placed) && p.state == ProbeState::kValid && p.dc == 0.0f;
  EXPECT_EQ(kept_dark, 27);
}

// The shared data's models, as the scene loader sees them: the bunny is closed (a solid), Suzanne
// is open at her eyes (noted, no solid).
TEST(SolidMesh, TheSceneSaysWhichModelsHaveAnInside) {
  const auto load = [](const std::string& file) {
    return parse_bake_scene(R"({"geometry": [{"kind": "gltf", "file": ")" + file +
                                R"(", "translation": [0,0,0]}],
                               "probes": {"min": [0,0,0], "max": [1,1,1], "spacing": 1}})",
                            "models.json", kData);
  };
  const BakeScene bunny = load("models/bunny.glb");
  EXPECT_EQ(bunny.solids.size(), 1u);
  EXPECT_TRUE(bunny.notes.empty());
  const BakeScene suzi = load("models/suzi.glb");
  EXPECT_TRUE(suzi.solids.empty());
  ASSERT_EQ(suzi.notes.size(), 1u);
  EXPECT_NE(suzi.notes[0].find("models/suzi.glb): open mesh (160 boundary"), std::string::npos)
      << suzi.notes[0];
}

}  // namespace
}  // namespace penumbra::probe_bake
