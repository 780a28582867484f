// SolidMesh: a closed triangle mesh (a glTF model) used as a solid by the probe bake's validity
// pass, so a probe inside a closed model is found invalid like one inside a box (probes inside
// geometry must never light dynamic objects: godotengine/godot #77168).
//
// Closed means watertight after welding vertices at equal positions (glTF splits vertices at
// normal and UV seams): every undirected edge is used by exactly two triangles. Orientation is
// not required. An open mesh (a boundary edge) or a non-manifold one (an edge of three or more
// triangles) has no inside; the bake scene keeps it as geometry only and says so
// (BakeScene::notes), as before.
//
// inside(p): the parity of the mesh's surface crossings along three fixed, irrational
// directions from p, by its own ray tracer (engine/reference, Embree), the majority of the three
// (a ray through an edge or grazing a silhouette may count one crossing too many or too few).
// Each crossing step is capped (a degenerate mesh cannot hang it). Threading: inside() is const
// and safe to call concurrently.
#pragma once

#include <cstddef>
#include <memory>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/mesh.h"

namespace penumbra::reference {
class Scene;
}

namespace penumbra::probe_bake {

struct MeshClosure {
  std::size_t welded_vertices = 0;    // distinct positions
  std::size_t edges = 0;              // distinct undirected edges (degenerate triangles skipped)
  std::size_t boundary_edges = 0;     // used by one triangle
  std::size_t nonmanifold_edges = 0;  // used by three or more
  bool closed() const { return edges > 0 && boundary_edges == 0 && nonmanifold_edges == 0; }
};

// Watertightness of `mesh` after welding equal positions.
MeshClosure mesh_closure(const data::MeshData& mesh);

class SolidMesh {
 public:
  // `mesh` under `transform` (object to world). Throws std::invalid_argument when the mesh is
  // not closed (the caller checks mesh_closure first).
  SolidMesh(const data::MeshData& mesh, const glm::mat4& transform);
  ~SolidMesh();
  SolidMesh(SolidMesh&&) noexcept;
  SolidMesh& operator=(SolidMesh&&) noexcept;

  // Is p strictly inside the closed surface? (Points on the surface: either answer.)
  bool inside(const glm::vec3& p) const;

 private:
  std::unique_ptr<reference::Scene> scene_;
  glm::vec3 lo_{0.0f}, hi_{0.0f};  // world bounding box
  float step_ = 0;                 // past each crossing, relative to the box
};

}  // namespace penumbra::probe_bake
