// Test helper: small glTF documents with one embedded (data URI) buffer, built field by field.
#pragma once

#include <nlohmann/json.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "penumbra/assets/gltf.h"
#include "test_support.h"

namespace penumbra::assets::test {

inline std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    if (i + 2 < in.size()) v |= static_cast<unsigned char>(in[i + 2]);
    out += k[v >> 18];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

template <class T>
std::string bytes_of(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  std::memcpy(s.data(), v.data(), s.size());
  return s;
}

struct GltfDoc {
  nlohmann::json j = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  int view(const std::string& bytes) {
    while (bin.size() % 4) bin.push_back('\0');
    j["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
    bin += bytes;
    return static_cast<int>(j["bufferViews"].size()) - 1;
  }
  int accessor(int view, int component, std::size_t count, const char* type) {
    j["accessors"].push_back(
        {{"bufferView", view}, {"componentType", component}, {"count", count}, {"type", type}});
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  std::string text() const {
    nlohmann::json out = j;
    out["buffers"] = {{{"byteLength", bin.size()},
                       {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return out.dump();
  }

  // One triangle (or `positions` / `indices` given), mesh 0 on node 0 in scene 0.
  static GltfDoc triangle(std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0},
                          std::vector<std::uint16_t> indices = {0, 1, 2}) {
    GltfDoc d;
    const int pos = d.accessor(d.view(bytes_of(positions)), 5126, positions.size() / 3, "VEC3");
    nlohmann::json prim = {{"attributes", {{"POSITION", pos}}}};
    if (!indices.empty())
      prim["indices"] = d.accessor(d.view(bytes_of(indices)), 5123, indices.size(), "SCALAR");
    d.j["meshes"] = {{{"name", "tri"}, {"primitives", nlohmann::json::array({prim})}}};
    d.j["nodes"] = {{{"mesh", 0}}};
    d.j["scenes"] = {{{"nodes", {0}}}};
    d.j["scene"] = 0;
    return d;
  }
};

inline Model load(const GltfDoc& d, const std::string& name = "doc.gltf") {
  const std::string s = d.text();
  return load_gltf_from_memory({reinterpret_cast<const unsigned char*>(s.data()), s.size()}, name);
}

inline void expect_error(const GltfDoc& d, const std::string& reason) {
  expect_load_error([&] { load(d); }, "doc.gltf", reason);
}

}  // namespace penumbra::assets::test
