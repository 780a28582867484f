// glTF 2.0 (.gltf, .glb) models: triangle meshes, node transforms, base colour.
//
// Contract: parsing by tinygltf 2.7 (images are not decoded), KHR_draco_mesh_compression
// decoded with libdraco, then validated here, because tinygltf accepts broken files: accessor
// and buffer-view bounds, index < vertex count, finite positions and transforms, an acyclic node
// forest (every node at most one parent). Modes TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN load
// as triangle lists; points and lines are skipped with a warning. Positions and normals may be
// float or integer (KHR_mesh_quantization, normalized or not); sparse accessors, accessors
// without a bufferView and unsupported required extensions are rejected.
// Normals that are zero or non-finite are dropped for that primitive (warning).
// Errors: LoadError naming the file and the reason (missing, truncated, bad JSON, index out of
// range, recursive nodes, ...). Threading: independent calls may run concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "penumbra/data/mesh.h"

namespace penumbra::assets {

// The glTF y-up frame to the engine's z-up frame: (x, y, z) -> (x, -z, y).
glm::mat4 gltf_to_engine();

struct Model {
  struct Instance {
    std::uint32_t mesh = 0;  // index into meshes
    std::int32_t node = -1;  // glTF node
    glm::mat4 world{1};      // object -> engine world (z-up), includes gltf_to_engine()
  };

  // One MeshData per triangle primitive ("<mesh name>/<primitive>"), immutable, shared by all
  // instances; positions and normals stay in glTF object space.
  std::vector<std::shared_ptr<const data::MeshData>> meshes;
  std::vector<Instance> instances;  // one per (node of the scene, primitive of its mesh)
  std::size_t gltf_mesh_count = 0;
  std::size_t node_count = 0;
  std::vector<std::string> warnings;  // skipped primitives, dropped normals, missing scene
  std::string source;

  std::size_t vertex_count() const;
  std::size_t triangle_count() const;
};

// The scene drawn is "scene" (else scene 0, else every root node).
Model load_gltf(const std::filesystem::path& path);

// `bytes` holds a .glb (magic "glTF") or .gltf JSON; external URIs resolve against `base_dir`,
// or are refused when it is empty. `name` is used in messages.
Model load_gltf_from_memory(std::span<const unsigned char> bytes, const std::string& name,
                            const std::filesystem::path& base_dir = {});

}  // namespace penumbra::assets
