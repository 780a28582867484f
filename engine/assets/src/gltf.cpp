// glTF 2.0 loader (gltf.h): tinygltf parses, this file validates and converts. Section numbers
// refer to the glTF 2.0 specification (registry.khronos.org/glTF/specs/2.0/glTF-2.0.html).
#include "penumbra/assets/gltf.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <string>
#include <utility>

#include "file_io.h"
#include "gltf_internal.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets {
namespace {

using detail::kMaxGltfElements;

// A validated accessor (section 3.6.2): every element lies inside its buffer.
struct View {
  const unsigned char* base = nullptr;
  std::size_t stride = 0, count = 0;
  int component = 0, components = 0;
  bool normalized = false;

  float get(std::size_t i, int c) const {
    const unsigned char* p = base + i * stride + c * tinygltf::GetComponentSizeInBytes(component);
    auto load = [p](auto v) {
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    switch (component) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return load(float{});
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return normalized ? std::fmax(load(std::int8_t{}) / 127.0f, -1.0f) : load(std::int8_t{});
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? load(std::uint8_t{}) / 255.0f : load(std::uint8_t{});
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return normalized ? std::fmax(load(std::int16_t{}) / 32767.0f, -1.0f)
                          : load(std::int16_t{});
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return normalized ? load(std::uint16_t{}) / 65535.0f : load(std::uint16_t{});
      default:
        return static_cast<float>(load(std::uint32_t{}));
    }
  }
  std::uint32_t index(std::size_t i) const {
    const unsigned char* p = base + i * stride;
    if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[0];
    if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) return p[0] | std::uint32_t{p[1]} << 8;
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
};

std::string type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    default:
      return "code " + std::to_string(type);
  }
}

class Converter {
 public:
  Converter(const tinygltf::Model& m, const std::string& name, Model& out)
      : m_(m), name_(name), out_(out) {}

  void run() {
    check_buffer_views();
    detail::MeshRanges ranges;
    for (std::size_t i = 0; i < m_.meshes.size(); ++i) {
      const std::size_t first = out_.meshes.size();
      for (std::size_t p = 0; p < m_.meshes[i].primitives.size(); ++p) convert_primitive(i, p);
      ranges.emplace_back(first, out_.meshes.size());
    }
    out_.gltf_mesh_count = m_.meshes.size();
    out_.node_count = m_.nodes.size();
    detail::place_instances(m_, ranges, name_, out_);
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(name_, reason); }

  void check_buffer_views() const {
    for (std::size_t i = 0; i < m_.bufferViews.size(); ++i) {
      const auto& bv = m_.bufferViews[i];
      const std::string where = "bufferView " + std::to_string(i) + ": ";
      if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size())
        fail(where + "buffer " + std::to_string(bv.buffer) + " out of range");
      const std::size_t size = m_.buffers[static_cast<std::size_t>(bv.buffer)].data.size();
      if (bv.byteOffset > size || bv.byteLength > size - bv.byteOffset)
        fail(where + "bytes [" + std::to_string(bv.byteOffset) + ", +" +
             std::to_string(bv.byteLength) + ") run past its buffer (" + std::to_string(size) +
             " bytes)");
      if (bv.byteStride != 0 && (bv.byteStride < 4 || bv.byteStride > 252))
        fail(where + "byteStride " + std::to_string(bv.byteStride) + " outside [4, 252]");
    }
  }

  View view(int index, int type, const std::string& what) const {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.accessors.size())
      fail(what + " accessor " + std::to_string(index) + " out of range");
    const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    const std::string where = what + " accessor " + std::to_string(index) + ": ";
    if (a.sparse.isSparse) fail(where + "sparse accessors are not supported");
    if (a.type != type) fail(where + "type " + type_name(a.type) + ", expected " + type_name(type));
    const int csize =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (csize <= 0 || csize > 4)
      fail(where + "component type " + std::to_string(a.componentType) + " not allowed");
    if (a.count > kMaxGltfElements) fail(where + "count " + std::to_string(a.count) + " too large");
    View v;
    v.count = a.count;
    v.component = a.componentType;
    v.components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    v.normalized = a.normalized;
    const std::size_t elem = static_cast<std::size_t>(csize) * v.components;
    // An accessor without a bufferView reads as zeros (section 3.6.2.1): useless geometry, and
    // a cheap way to make a loader allocate `count` elements, so it is rejected.
    if (a.bufferView < 0) fail(where + "no bufferView");
    if (static_cast<std::size_t>(a.bufferView) >= m_.bufferViews.size())
      fail(where + "bufferView " + std::to_string(a.bufferView) + " out of range");
    const auto& bv = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    v.stride = bv.byteStride != 0 ? bv.byteStride : elem;
    if (v.stride < elem) fail(where + "byteStride smaller than an element");
    if (v.count > 0 && (a.byteOffset > bv.byteLength ||
                        (v.count - 1) * v.stride + elem > bv.byteLength - a.byteOffset))
      fail(where + std::to_string(v.count) + " elements run past bufferView " +
           std::to_string(a.bufferView));
    v.base =
        m_.buffers[static_cast<std::size_t>(bv.buffer)].data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  std::vector<glm::vec3> read_vec3(int index, const std::string& what) const {
    const View v = view(index, TINYGLTF_TYPE_VEC3, what);
    std::vector<glm::vec3> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) out[i] = {v.get(i, 0), v.get(i, 1), v.get(i, 2)};
    return out;
  }

  std::vector<std::uint32_t> read_indices(int index, const std::string& what) const {
    if (index >= 0 && static_cast<std::size_t>(index) < m_.accessors.size()) {
      const int c = m_.accessors[static_cast<std::size_t>(index)].componentType;
      if (c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
          c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        fail(what + " accessor " + std::to_string(index) + ": indices must be unsigned integers");
    }
    const View v = view(index, TINYGLTF_TYPE_SCALAR, what);
    std::vector<std::uint32_t> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) out[i] = v.index(i);
    return out;
  }

  // Strips and fans to lists (section 3.7.2.1).
  static std::vector<std::uint32_t> to_list(const std::vector<std::uint32_t>& in, int mode) {
    if (mode == TINYGLTF_MODE_TRIANGLES || in.size() < 3)
      return mode == TINYGLTF_MODE_TRIANGLES ? in : std::vector<std::uint32_t>{};
    std::vector<std::uint32_t> out;
    out.reserve(3 * (in.size() - 2));
    for (std::size_t i = 0; i + 2 < in.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
        out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
      else
        out.insert(out.end(), {in[i], in[i + 1 + i % 2], in[i + 2 - i % 2]});
    }
    return out;
  }

  void convert_primitive(std::size_t mi, std::size_t pi) {
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    const tinygltf::Primitive& prim = mesh.primitives[pi];
    const std::string where =
        "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": ";
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      out_.warnings.push_back(where + "mode " + std::to_string(prim.mode) +
                              " is not triangles; skipped");
      return;
    }
    auto data = std::make_shared<data::MeshData>();
    data->name =
        (mesh.name.empty() ? "mesh" + std::to_string(mi) : mesh.name) + "/" + std::to_string(pi);
    std::vector<std::uint32_t> indices;
    const bool draco = prim.extensions.count("KHR_draco_mesh_compression") != 0;
    const int mode = draco ? TINYGLTF_MODE_TRIANGLES : prim.mode;  // Draco stores triangle lists
    if (draco) {
      detail::DecodedPrimitive d = detail::decode_draco(m_, prim, name_, where);
      data->positions = std::move(d.positions);
      data->normals = std::move(d.normals);
      indices = std::move(d.indices);
    } else {
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail(where + "no POSITION attribute");
      data->positions = read_vec3(pos->second, where + "POSITION");
      if (const auto nrm = prim.attributes.find("NORMAL"); nrm != prim.attributes.end())
        data->normals = read_vec3(nrm->second, where + "NORMAL");
      if (prim.indices >= 0) {
        indices = read_indices(prim.indices, where + "indices");
      } else {
        indices.resize(data->positions.size());
        for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<std::uint32_t>(i);
      }
    }
    const std::size_t n = data->positions.size();
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3& p = data->positions[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail(where + "position " + std::to_string(i) + " is not finite");
    }
    for (std::size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= n)
        fail(where + "index " + std::to_string(i) + " = " + std::to_string(indices[i]) +
             " out of range (" + std::to_string(n) + " vertices)");
    if (mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
      fail(where + std::to_string(indices.size()) + " indices, not a multiple of 3");
    data->indices = to_list(indices, mode);
    if (data->indices.empty()) {
      out_.warnings.push_back(where + "no triangles; skipped");
      return;
    }
    check_normals(*data, where);
    data->base_color = base_color(prim.material, where);
    out_.meshes.push_back(std::move(data));
  }

  void check_normals(data::MeshData& data, const std::string& where) {
    if (data.normals.empty()) return;
    if (data.normals.size() != data.positions.size())
      fail(where + std::to_string(data.normals.size()) + " normals for " +
           std::to_string(data.positions.size()) + " positions");
    std::size_t bad = 0;
    for (glm::vec3& v : data.normals) {
      const float len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
      if (!std::isfinite(len) || len < 1e-12f)
        ++bad;
      else
        v /= len;
    }
    if (bad > 0) {
      out_.warnings.push_back(where + std::to_string(bad) +
                              " normals are zero or not finite; normals dropped");
      data.normals.clear();
    }
  }

  glm::vec4 base_color(int material, const std::string& where) const {
    if (material < 0) return glm::vec4(1.0f);
    if (static_cast<std::size_t>(material) >= m_.materials.size())
      fail(where + "material " + std::to_string(material) + " out of range");
    const auto& f =
        m_.materials[static_cast<std::size_t>(material)].pbrMetallicRoughness.baseColorFactor;
    if (f.size() != 4) fail(where + "baseColorFactor needs 4 numbers");
    glm::vec4 c;
    for (int i = 0; i < 4; ++i) {
      if (!std::isfinite(f[i])) fail(where + "baseColorFactor is not finite");
      c[i] = static_cast<float>(f[i]);
    }
    return c;
  }

  const tinygltf::Model& m_;
  const std::string& name_;
  Model& out_;
};

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                  const unsigned char*, int, void*) {
  return true;
}
bool no_file_exists(const std::string&, void*) {
  return false;
}
std::string no_expand(const std::string& path, void*) {
  return path;
}
bool no_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "external file " + path + " refused (loading from memory)\n";
  return false;
}
bool no_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
  return false;
}

}  // namespace

glm::mat4 gltf_to_engine() {
  return glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, -1, 0, 0),
                   glm::vec4(0, 0, 0, 1));
}

std::size_t Model::vertex_count() const {
  std::size_t n = 0;
  for (const auto& m : meshes) n += m->positions.size();
  return n;
}

std::size_t Model::triangle_count() const {
  std::size_t n = 0;
  for (const auto& m : meshes) n += m->indices.size() / 3;
  return n;
}

Model load_gltf_from_memory(std::span<const unsigned char> bytes, const std::string& name,
                            const std::filesystem::path& base_dir) {
  const detail::PreparedGltf prepared = detail::prepare_gltf(bytes, name);
  if (prepared.bytes.size() > 0xFFFFFFFFu) throw LoadError(name, "file too large");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignore_image, nullptr);
  if (base_dir.empty())
    loader.SetFsCallbacks({&no_file_exists, &no_expand, &no_read, &no_write, nullptr});
  tinygltf::Model m;
  std::string err, warn;
  bool ok = false;
  try {
    const auto size = static_cast<unsigned>(prepared.bytes.size());
    ok = prepared.binary
             ? loader.LoadBinaryFromMemory(&m, &err, &warn, prepared.bytes.data(), size,
                                           base_dir.string())
             : loader.LoadASCIIFromString(&m, &err, &warn,
                                          reinterpret_cast<const char*>(prepared.bytes.data()),
                                          size, base_dir.string());
  } catch (const std::exception& e) {
    throw LoadError(name, std::string("tinygltf: ") + e.what());
  }
  while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
  for (char& c : err)
    if (c == '\n') c = ';';
  if (!ok) throw LoadError(name, "tinygltf: " + (err.empty() ? std::string("parse failed") : err));
  for (const std::string& ext : m.extensionsRequired)
    if (ext != "KHR_draco_mesh_compression" && ext != "KHR_mesh_quantization")
      throw LoadError(name, "required extension " + ext + " is not supported");
  Model out;
  out.source = name;
  Converter(m, name, out).run();
  return out;
}

Model load_gltf(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = detail::read_file(path);
  std::filesystem::path base = path.parent_path();
  if (base.empty()) base = ".";
  return load_gltf_from_memory(bytes, path.string(), base);
}

}  // namespace penumbra::assets
