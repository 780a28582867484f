#include "penumbra/assets/gltf.h"

#include <gtest/gtest.h>

#include <limits>
#include <map>

#include "common/stability.h"
#include "gltf_builder.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_error;
using test::expect_load_error;
using test::GltfDoc;
using test::load;

TEST(Gltf, TriangleLoads) {
  const Model m = load(GltfDoc::triangle());
  ASSERT_EQ(m.meshes.size(), 1u);
  EXPECT_EQ(m.meshes[0]->name, "tri/0");
  EXPECT_EQ(m.meshes[0]->indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(m.vertex_count(), 3u);
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.meshes[0]->base_color, glm::vec4(1.0f));
  ASSERT_EQ(m.instances.size(), 1u);
  EXPECT_EQ(m.instances[0].world, gltf_to_engine());
  EXPECT_TRUE(m.warnings.empty());
}

TEST(Gltf, BaseColorStripsFansAndSkippedModes) {
  GltfDoc d = GltfDoc::triangle({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, {});
  d.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 0.75}}}}}};
  auto prim = d.j["meshes"][0]["primitives"][0];
  prim["material"] = 0;
  d.j["meshes"][0]["primitives"] = nlohmann::json::array();
  for (int mode : {4, 5, 6, 0, 1, 2, 3}) {
    prim["mode"] = mode;
    d.j["meshes"][0]["primitives"].push_back(prim);
  }
  d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 0;
  // Mode 4 needs a multiple of 3 vertices: give it its own 3-vertex accessor.
  d.j["accessors"].push_back(d.j["accessors"][0]);
  d.j["accessors"][1]["count"] = 3;
  d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 1;
  const Model m = load(d);
  ASSERT_EQ(m.meshes.size(), 3u);
  EXPECT_EQ(m.meshes[0]->base_color, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  EXPECT_EQ(m.meshes[0]->indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(m.meshes[1]->indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));  // strip
  EXPECT_EQ(m.meshes[2]->indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0}));  // fan
  ASSERT_EQ(m.warnings.size(), 4u);
  EXPECT_NE(m.warnings[0].find("primitive 3: mode 0 is not triangles; skipped"), std::string::npos)
      << m.warnings[0];
  EXPECT_EQ(m.instances.size(), 3u);
}

TEST(Gltf, BadNormalsAreDropped) {
  PENUMBRA_STABILITY("zero or non-finite normals in a glTF mesh",
                     "the normals dropped with a warning (recomputed)", "-");
  GltfDoc d = GltfDoc::triangle();
  const std::vector<float> normals = {0, 0, 2, 0, 0, 0, 0, 0, 1};
  d.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] =
      d.accessor(d.view(test::bytes_of(normals)), 5126, 3, "VEC3");
  const Model m = load(d);
  EXPECT_TRUE(m.meshes[0]->normals.empty());
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("1 normals are zero or not finite"), std::string::npos);
  const std::vector<float> good = {0, 0, 2, 0, 3, 0, 0, 0, 1};
  d.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] =
      d.accessor(d.view(test::bytes_of(good)), 5126, 3, "VEC3");
  EXPECT_EQ(load(d).meshes[0]->normals[1], glm::vec3(0, 1, 0));  // normalised
}

TEST(Gltf, InvalidIndicesPositionsAndAccessors) {
  PENUMBRA_STABILITY("indices out of range, NaN positions, accessors past their buffers",
                     "LoadError", "-");
  expect_error(GltfDoc::triangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 3}),
               "index 2 = 3 out of range (3 vertices)");
  expect_error(GltfDoc::triangle({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0}),
               "4 indices, not a multiple of 3");
  const float inf = std::numeric_limits<float>::infinity(),
              nan = std::numeric_limits<float>::quiet_NaN();
  expect_error(GltfDoc::triangle({0, 0, 0, inf, 0, 0, 0, 1, 0}), "position 1 is not finite");
  expect_error(GltfDoc::triangle({0, 0, 0, 1, 0, 0, 0, nan, 0}), "position 2 is not finite");

  GltfDoc past = GltfDoc::triangle();
  past.j["accessors"][0]["count"] = 4;
  expect_error(past, "4 elements run past bufferView 0");
  GltfDoc offset = GltfDoc::triangle();
  offset.j["accessors"][0]["byteOffset"] = 4;
  expect_error(offset, "run past bufferView");
  GltfDoc view = GltfDoc::triangle();
  view.j["bufferViews"][0]["byteLength"] = 4096;
  expect_error(view, "run past its buffer");
  GltfDoc type = GltfDoc::triangle();
  type.j["accessors"][0]["type"] = "VEC2";
  expect_error(type, "POSITION accessor 0: type VEC2, expected VEC3");
  GltfDoc zeros = GltfDoc::triangle();
  zeros.j["accessors"][0].erase("bufferView");
  zeros.j["accessors"][0]["count"] = 1 << 25;
  expect_error(zeros, "POSITION accessor 0: no bufferView");
  GltfDoc comp = GltfDoc::triangle();
  comp.j["accessors"][1]["componentType"] = 5126;
  expect_error(comp, "indices must be unsigned integers");
  GltfDoc sparse = GltfDoc::triangle();
  sparse.j["accessors"][0]["sparse"] = {{"count", 1},
                                        {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                        {"values", {{"bufferView", 0}}}};
  expect_error(sparse, "sparse accessors are not supported");
  GltfDoc missing = GltfDoc::triangle();
  missing.j["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
  missing.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 0;
  expect_error(missing, "no POSITION attribute");
  GltfDoc material = GltfDoc::triangle();
  material.j["meshes"][0]["primitives"][0]["material"] = 3;
  expect_error(material, "material 3 out of range");
  GltfDoc ext = GltfDoc::triangle();
  ext.j["extensionsRequired"] = {"KHR_unknown_thing"};
  expect_error(ext, "required extension KHR_unknown_thing is not supported");
}

TEST(Gltf, GarbageTruncatedAndMissingFiles) {
  PENUMBRA_STABILITY("garbage, truncated and missing glTF files", "LoadError naming the file", "-");
  test::TempDir dir;
  expect_load_error([&] { load_gltf(dir.file("none.glb")); }, "none.glb", "no such file");
  expect_load_error([&] { load_gltf(dir.write("empty.gltf", "")); }, "empty.gltf", "empty file");
  expect_load_error([&] { load_gltf(dir.write("garbage.gltf", std::string(300, '\x9c'))); },
                    "garbage.gltf", "tinygltf");
  const std::string good = GltfDoc::triangle().text();
  ASSERT_NO_THROW(load_gltf(dir.write("good.gltf", good)));
  for (std::size_t cut : {std::size_t{1}, good.size() / 3, good.size() - 2})
    expect_load_error([&] { load_gltf(dir.write("cut.gltf", good.substr(0, cut))); }, "cut.gltf",
                      "tinygltf");
  GltfDoc external = GltfDoc::triangle();
  const std::string text = external.text();
  nlohmann::json j = nlohmann::json::parse(text);
  j["buffers"][0]["uri"] = "triangle.bin";
  const std::string ext_text = j.dump();
  expect_load_error(
      [&] {
        load_gltf_from_memory(
            {reinterpret_cast<const unsigned char*>(ext_text.data()), ext_text.size()}, "mem");
      },
      "mem", "triangle.bin");
  expect_load_error([&] { load_gltf(dir.write("ext.gltf", ext_text)); }, "ext.gltf", "tinygltf");
}

// Debian's assimp-testmodels glTF 2.0 corpus: every file loads or is rejected with a message.
TEST(Gltf, AssimpCorpusLoadsOrFailsCleanly) {
  PENUMBRA_STABILITY("assimp's glTF 2.0 corpus, broken files included",
                     "every file loads or is rejected with a message", "-");
  const std::map<std::string, std::string> must_fail = {
      {"IndexOutOfRange/IndexOutOfRange.gltf", "out of range"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "out of range"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "is not finite"},
      {"RecursiveNodes/RecursiveNodes.gltf", "recursive node graph"},
      {"MissingBin/BoxTextured.gltf", "tinygltf"},
  };
  const std::map<std::string, std::pair<std::size_t, std::size_t>> must_load = {
      // vertices, triangles
      {"BoxTextured-glTF-Binary/BoxTextured.glb", {24, 12}},
      {"BoxTextured-glTF/BoxTextured.gltf", {24, 12}},
      {"BoxTextured-glTF-Embedded/BoxTextured.gltf", {24, 12}},
      {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", {0, 0}},
      {"draco/2CylinderEngine.gltf", {0, 0}},
  };
  std::size_t files = 0, loaded = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::assimp_gltf2())) {
    const std::string ext = e.path().extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    ++files;
    const std::string rel = std::filesystem::relative(e.path(), test::assimp_gltf2()).string();
    try {
      const Model m = load_gltf(e.path());
      ++loaded;
      EXPECT_FALSE(must_fail.count(rel)) << rel << " loaded";
      if (const auto it = must_load.find(rel); it != must_load.end() && it->second.first > 0) {
        EXPECT_EQ(m.vertex_count(), it->second.first) << rel;
        EXPECT_EQ(m.triangle_count(), it->second.second) << rel;
      }
      for (const auto& mesh : m.meshes)
        for (std::uint32_t i : mesh->indices) ASSERT_LT(i, mesh->positions.size()) << rel;
    } catch (const LoadError& err) {
      EXPECT_EQ(err.file(), e.path().string());
      EXPECT_FALSE(err.reason().empty()) << rel;
      EXPECT_FALSE(must_load.count(rel)) << rel << ": " << err.what();
      if (const auto it = must_fail.find(rel); it != must_fail.end()) {
        EXPECT_NE(err.reason().find(it->second), std::string::npos) << err.what();
      }
      std::printf("  rejected %s\n", err.what());
    }
  }
  EXPECT_GE(files, 40u) << "assimp-testmodels corpus missing?";
  EXPECT_GE(loaded, 25u);
  std::printf("  %zu of %zu corpus files loaded\n", loaded, files);
}

}  // namespace
}  // namespace penumbra::assets
