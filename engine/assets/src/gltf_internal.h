// Internal to the glTF loader (gltf.cpp): the container pre-pass (gltf_container.cpp), the
// Draco decoder (gltf_draco.cpp) and the node hierarchy (gltf_nodes.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/assets/gltf.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace penumbra::assets::detail {

inline constexpr std::size_t kMaxGltfElements = std::size_t{1} << 26;

struct PreparedGltf {
  std::vector<unsigned char> bytes;  // what tinygltf parses
  bool binary = false;               // .glb container
};

// Checks the GLB container (glTF 2.0 spec section 4.4: 12-byte header, JSON chunk, optional BIN
// chunk) and removes "indices" from Draco-compressed primitives: tinygltf 2.7 built without its
// own (unchecked) Draco code rejects their indices accessor, which has no bufferView; the faces
// come from the Draco stream instead. Throws LoadError(name, reason).
PreparedGltf prepare_gltf(std::span<const unsigned char> bytes, const std::string& name);

struct DecodedPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      // empty when the extension has no NORMAL
  std::vector<std::uint32_t> indices;  // triangle list, validated < positions.size()
};

// Decodes primitive.extensions["KHR_draco_mesh_compression"]. Throws LoadError(name, where +
// reason) on a bad extension object, buffer view, Draco bit stream or attribute.
DecodedPrimitive decode_draco(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                              const std::string& name, const std::string& where);

// [first, end) in Model::meshes of each glTF mesh's triangle primitives.
using MeshRanges = std::vector<std::pair<std::size_t, std::size_t>>;

// Validates the node graph (section 3.5: children in range, at most one parent, no cycles,
// scene nodes are roots), composes each node's TRS or matrix from the scene's roots down
// (prefixed by gltf_to_engine()) and appends one Model::Instance per primitive of each node's
// mesh. Scene: "scene", else scene 0, else every root node (with a warning).
void place_instances(const tinygltf::Model& model, const MeshRanges& ranges,
                     const std::string& name, Model& out);

}  // namespace penumbra::assets::detail
