// Fewer triangles for a mesh seen small: edge collapses under a geometric error bound, by
// meshoptimizer's meshopt_simplify (quadric error, the topology kept), then the unused vertices
// dropped. The kept vertices are original ones, with their own normals, so a simplified mesh
// can serve as a cheaper set of lighting receivers as well as a cheaper draw.
//
// Errors: std::invalid_argument naming the mesh for no triangles, indices out of range or a
// target ratio outside (0, 1]. A mesh that cannot be simplified within max_error comes back
// with as few triangles as the bound allows (possibly all of them).
// Threading: pure function.
#pragma once

#include "penumbra/data/mesh.h"

namespace penumbra::assets {

struct SimplifyOptions {
  float target_ratio = 0.25f;  // at most this share of the triangles is kept
  // Largest deviation allowed, relative to the mesh's extent (its bounding box's largest side).
  float max_error = 0.01f;
};

struct SimplifiedMesh {
  data::MeshData mesh;
  float error = 0;  // the deviation reached, relative to the extent
};

SimplifiedMesh simplify_mesh(const data::MeshData& mesh, const SimplifyOptions& options = {});

}  // namespace penumbra::assets
