// KHR_draco_mesh_compression (github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Khronos/
// KHR_draco_mesh_compression): the bufferView holds a Draco mesh; "attributes" maps glTF
// attribute names to Draco unique attribute ids.
#include <draco/compression/decode.h>
#include <tiny_gltf.h>

#include <string>

#include "gltf_internal.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets::detail {
namespace {

std::vector<glm::vec3> read_attribute(const draco::Mesh& mesh, const tinygltf::Value& attributes,
                                      const char* semantic, const std::string& name,
                                      const std::string& where) {
  const tinygltf::Value& id = attributes.Get(semantic);
  if (!id.IsInt()) return {};
  const draco::PointAttribute* att =
      mesh.GetAttributeByUniqueId(static_cast<uint32_t>(id.Get<int>()));
  if (att == nullptr)
    throw LoadError(name, where + "Draco stream has no attribute " + std::to_string(id.Get<int>()) +
                              " for " + semantic);
  if (att->num_components() < 3)
    throw LoadError(name, where + "Draco " + semantic + " has " +
                              std::to_string(int{att->num_components()}) + " components, not 3");
  std::vector<glm::vec3> out(mesh.num_points());
  for (draco::PointIndex i(0); i < mesh.num_points(); ++i) {
    const draco::AttributeValueIndex v = att->mapped_index(i);
    float xyz[3];
    if (v.value() >= att->size() || !att->ConvertValue<float>(v, 3, xyz))
      throw LoadError(name, where + "Draco " + semantic + " value " + std::to_string(i.value()) +
                                " cannot be read");
    out[i.value()] = {xyz[0], xyz[1], xyz[2]};
  }
  return out;
}

}  // namespace

DecodedPrimitive decode_draco(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                              const std::string& name, const std::string& where) {
  const tinygltf::Value& ext = primitive.extensions.at("KHR_draco_mesh_compression");
  const tinygltf::Value& view_index = ext.Get("bufferView");
  const tinygltf::Value& attributes = ext.Get("attributes");
  if (!view_index.IsInt() || !attributes.IsObject())
    throw LoadError(name, where + "KHR_draco_mesh_compression needs bufferView and attributes");
  const int v = view_index.Get<int>();
  if (v < 0 || static_cast<std::size_t>(v) >= model.bufferViews.size())
    throw LoadError(name, where + "Draco bufferView " + std::to_string(v) + " out of range");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(v)];
  // gltf.cpp has checked every buffer view against its buffer.
  const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
  draco::DecoderBuffer in;
  in.Init(reinterpret_cast<const char*>(buffer.data.data() + view.byteOffset), view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok())
    throw LoadError(name, where + "Draco decode failed: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (mesh == nullptr) throw LoadError(name, where + "Draco decode returned no mesh");
  if (mesh->num_points() > kMaxGltfElements || mesh->num_faces() > kMaxGltfElements)
    throw LoadError(name, where + "Draco mesh too large");

  DecodedPrimitive out;
  out.positions = read_attribute(*mesh, attributes, "POSITION", name, where);
  if (out.positions.empty() && mesh->num_points() > 0)
    throw LoadError(name, where + "Draco extension has no POSITION attribute");
  out.normals = read_attribute(*mesh, attributes, "NORMAL", name, where);
  out.indices.reserve(std::size_t{mesh->num_faces()} * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = mesh->face(f)[k].value();
      if (index >= mesh->num_points())
        throw LoadError(name, where + "Draco face " + std::to_string(f.value()) + " index " +
                                  std::to_string(index) + " out of range (" +
                                  std::to_string(mesh->num_points()) + " points)");
      out.indices.push_back(index);
    }
  }
  return out;
}

}  // namespace penumbra::assets::detail
