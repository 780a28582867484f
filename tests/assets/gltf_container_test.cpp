#include <gtest/gtest.h>

#include "common/stability.h"
#include "gltf_builder.h"
#include "gltf_internal.h"
#include "penumbra/assets/gltf.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

std::string le32(std::uint32_t v) {
  return {static_cast<char>(v), static_cast<char>(v >> 8), static_cast<char>(v >> 16),
          static_cast<char>(v >> 24)};
}

std::string glb(const std::string& json, std::string bin, std::uint32_t version = 2) {
  std::string j = json;
  while (j.size() % 4) j.push_back(' ');
  while (bin.size() % 4) bin.push_back('\0');
  std::string out =
      "glTF" + le32(version) + le32(0) + le32(static_cast<std::uint32_t>(j.size())) + "JSON" + j;
  if (!bin.empty())
    out += le32(static_cast<std::uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
  const std::string total = le32(static_cast<std::uint32_t>(out.size()));
  out.replace(8, 4, total);
  return out;
}

Model load(const std::string& bytes) {
  return load_gltf_from_memory({reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()},
                               "c.glb");
}

// The triangle document with its buffer in the GLB BIN chunk instead of a data URI.
std::string triangle_glb() {
  test::GltfDoc d = test::GltfDoc::triangle();
  nlohmann::json j = d.j;
  j["buffers"] = {{{"byteLength", d.bin.size()}}};
  return glb(j.dump(), d.bin);
}

TEST(GltfContainer, GlbLoads) {
  const Model m = load(triangle_glb());
  EXPECT_EQ(m.triangle_count(), 1u);
}

TEST(GltfContainer, BadGlbContainers) {
  PENUMBRA_STABILITY(
      "GLB containers with zero or huge chunk lengths, a BIN chunk that does not fit",
      "LoadError (a length underflow found by fuzz_gltf)", "fuzz target replayed in ctest");
  const std::string good = triangle_glb();
  expect_load_error([&] { load(good.substr(0, 15)); }, "c.glb", "truncated GLB header");
  expect_load_error([&] { load(good.substr(0, good.size() - 4)); }, "c.glb",
                    "truncated GLB: header says");
  std::string zero_length = good;
  zero_length.replace(8, 4, le32(0));  // found by fuzz_gltf: the length underflowed
  expect_load_error([&] { load(zero_length); }, "c.glb", "GLB header length 0 is too small");
  std::string v1 = good;
  v1[4] = 1;
  expect_load_error([&] { load(v1); }, "c.glb", "GLB version 1, not 2");
  std::string json_len = good;
  json_len.replace(12, 4, le32(1u << 30));
  expect_load_error([&] { load(json_len); }, "c.glb", "JSON chunk runs past the end");
  std::string not_json = good;
  not_json[16] = 'X';
  expect_load_error([&] { load(not_json); }, "c.glb", "first chunk is not JSON");
  // The BIN chunk must fit too.
  nlohmann::json j = nlohmann::json::parse(R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[
      {"attributes":{"POSITION":0},"indices":1,"extensions":{"KHR_draco_mesh_compression":{}}}]}]})");
  std::string draco = glb(j.dump(), std::string(16, '\0'));
  draco.replace(draco.size() - 24, 4, le32(1000));
  expect_load_error([&] { load(draco); }, "c.glb", "BIN chunk runs past the end");
}

TEST(GltfContainer, DracoPrimitivesLoseTheirIndicesOnly) {
  const std::string text = R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[
      {"attributes":{"POSITION":0},"indices":1,"extensions":{"KHR_draco_mesh_compression":{"bufferView":0}}},
      {"attributes":{"POSITION":0},"indices":1}]}]})";
  const auto prepared =
      detail::prepare_gltf({reinterpret_cast<const unsigned char*>(text.data()), text.size()}, "p");
  EXPECT_FALSE(prepared.binary);
  const nlohmann::json j = nlohmann::json::parse(prepared.bytes.begin(), prepared.bytes.end());
  EXPECT_FALSE(j["meshes"][0]["primitives"][0].contains("indices"));
  EXPECT_TRUE(j["meshes"][0]["primitives"][1].contains("indices"));

  const std::string bin(12, 'b');
  const std::string packed = glb(text, bin);
  const auto p2 = detail::prepare_gltf(
      {reinterpret_cast<const unsigned char*>(packed.data()), packed.size()}, "p");
  ASSERT_TRUE(p2.binary);
  const std::string out(p2.bytes.begin(), p2.bytes.end());
  EXPECT_EQ(out.size() % 4, 0u);
  EXPECT_EQ(out.substr(out.size() - 12), bin);
  EXPECT_EQ(out.substr(8, 4), le32(static_cast<std::uint32_t>(out.size())));
  expect_load_error([&] { detail::prepare_gltf({}, "p"); }, "p", "empty file");
  const std::string broken = R"({"KHR_draco_mesh_compression": [)";
  expect_load_error(
      [&] {
        detail::prepare_gltf({reinterpret_cast<const unsigned char*>(broken.data()), broken.size()},
                             "p");
      },
      "p", "not valid JSON");
}

}  // namespace
}  // namespace penumbra::assets
