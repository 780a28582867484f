// The GLB container and the Draco pre-pass before tinygltf (gltf_internal.h).
#include <nlohmann/json.hpp>

#include <cstring>
#include <string>
#include <string_view>

#include "gltf_internal.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets::detail {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr const char* kDraco = "KHR_draco_mesh_compression";

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}

void put_le32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

// Removes "indices" from primitives that carry the Draco extension; false if nothing changed.
bool strip_draco_indices(std::string_view json_text, std::string& out, const std::string& name) {
  if (json_text.find(kDraco) == std::string_view::npos) return false;
  nlohmann::json j = nlohmann::json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (j.is_discarded()) throw LoadError(name, "JSON chunk is not valid JSON");
  bool changed = false;
  const auto meshes = j.is_object() ? j.find("meshes") : j.end();
  if (meshes == j.end() || !meshes->is_array()) return false;
  for (auto& mesh : *meshes) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
      continue;
    for (auto& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("extensions")) continue;
      const auto& ext = prim["extensions"];
      if (ext.is_object() && ext.contains(kDraco) && prim.contains("indices")) {
        prim.erase("indices");
        changed = true;
      }
    }
  }
  if (changed) out = j.dump();
  return changed;
}

}  // namespace

PreparedGltf prepare_gltf(std::span<const unsigned char> bytes, const std::string& name) {
  PreparedGltf out;
  if (bytes.empty()) throw LoadError(name, "empty file");
  if (bytes.size() < 4 || le32(bytes.data()) != kMagic) {
    // .gltf: JSON text.
    std::string rewritten;
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (strip_draco_indices(text, rewritten, name))
      out.bytes.assign(rewritten.begin(), rewritten.end());
    else
      out.bytes.assign(bytes.begin(), bytes.end());
    return out;
  }
  out.binary = true;
  if (bytes.size() < 20) throw LoadError(name, "truncated GLB header");
  const std::uint32_t version = le32(bytes.data() + 4), length = le32(bytes.data() + 8);
  if (version != 2) throw LoadError(name, "GLB version " + std::to_string(version) + ", not 2");
  if (length < 20)
    throw LoadError(name, "GLB header length " + std::to_string(length) + " is too small");
  if (length > bytes.size())
    throw LoadError(name, "truncated GLB: header says " + std::to_string(length) +
                              " bytes, file has " + std::to_string(bytes.size()));
  const std::uint32_t json_len = le32(bytes.data() + 12);
  if (le32(bytes.data() + 16) != kChunkJson) throw LoadError(name, "GLB: first chunk is not JSON");
  if (json_len > length - 20) throw LoadError(name, "GLB: JSON chunk runs past the end");
  const std::string_view json(reinterpret_cast<const char*>(bytes.data() + 20), json_len);
  std::size_t pos = 20 + std::size_t{json_len};
  std::span<const unsigned char> bin;
  bool has_bin = false;
  if (pos + 8 <= length) {
    const std::uint32_t bin_len = le32(bytes.data() + pos);
    if (le32(bytes.data() + pos + 4) == kChunkBin) {
      if (bin_len > length - pos - 8) throw LoadError(name, "GLB: BIN chunk runs past the end");
      bin = bytes.subspan(pos + 8, bin_len);
      has_bin = true;
    }
  }
  std::string rewritten;
  if (!strip_draco_indices(json, rewritten, name)) {
    out.bytes.assign(bytes.begin(), bytes.begin() + length);
    return out;
  }
  while (rewritten.size() % 4 != 0) rewritten.push_back(' ');
  const std::size_t bin_chunk = has_bin ? 8 + (bin.size() + 3) / 4 * 4 : 0;
  const std::size_t total = 20 + rewritten.size() + bin_chunk;
  if (total > 0xFFFFFFFFu) throw LoadError(name, "GLB too large");
  out.bytes.reserve(total);
  put_le32(out.bytes, kMagic);
  put_le32(out.bytes, 2);
  put_le32(out.bytes, static_cast<std::uint32_t>(total));
  put_le32(out.bytes, static_cast<std::uint32_t>(rewritten.size()));
  put_le32(out.bytes, kChunkJson);
  out.bytes.insert(out.bytes.end(), rewritten.begin(), rewritten.end());
  if (has_bin) {
    put_le32(out.bytes, static_cast<std::uint32_t>((bin.size() + 3) / 4 * 4));
    put_le32(out.bytes, kChunkBin);
    out.bytes.insert(out.bytes.end(), bin.begin(), bin.end());
    out.bytes.resize(total, 0);
  }
  return out;
}

}  // namespace penumbra::assets::detail
