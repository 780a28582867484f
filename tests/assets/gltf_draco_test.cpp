#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "common/stability.h"
#include "penumbra/assets/gltf.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

struct Expected {
  const char* file;
  std::size_t vertices, triangles;
  glm::vec3 lo, hi;  // the POSITION accessor's min / max in the file
  glm::vec4 color;
};

TEST(GltfDraco, SharedModelsDecode) {
  const Expected models[] = {
      {"bunny.glb",
       2826,
       5648,
       {-0.91377f, -0.89104f, -0.69637f},
       {0.91721f, 0.93988f, 0.69886f},
       {0.8f, 0.8f, 0.8f, 1}},
      {"suzi.glb",
       7503,
       14842,
       {-0.92973f, -0.66979f, -0.54479f},
       {0.92973f, 0.66825f, 0.57616f},
       {1, 1, 1, 1}},
  };
  for (const Expected& e : models) {
    const auto path = test::shared_data() / "models" / e.file;
    const auto t0 = std::chrono::steady_clock::now();
    Model m;
    ASSERT_NO_THROW(m = load_gltf(path)) << path;
    std::printf(
        "  %-10s %.2f ms\n", e.file,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    ASSERT_EQ(m.meshes.size(), 1u);
    const data::MeshData& mesh = *m.meshes[0];
    EXPECT_EQ(mesh.positions.size(), e.vertices) << e.file;
    EXPECT_EQ(mesh.indices.size(), 3 * e.triangles) << e.file;
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    for (const glm::vec3& n : mesh.normals)
      ASSERT_NEAR(std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z), 1.0f, 1e-4f);
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    for (int k = 0; k < 3; ++k) {  // Draco quantisation keeps the bounds to about 1e-3
      EXPECT_NEAR(lo[k], e.lo[k], 2e-3f) << e.file << " axis " << k;
      EXPECT_NEAR(hi[k], e.hi[k], 2e-3f) << e.file << " axis " << k;
    }
    EXPECT_EQ(mesh.base_color, e.color) << e.file;
    EXPECT_EQ(m.instances.size(), 1u);
    EXPECT_TRUE(m.warnings.empty());
  }
}

TEST(GltfDraco, AssimpDracoEngineDecodes) {
  const Model draco = load_gltf(test::assimp_gltf2() / "draco" / "2CylinderEngine.gltf");
  const Model plain =
      load_gltf(test::assimp_gltf2() / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb");
  EXPECT_EQ(draco.instances.size(), plain.instances.size());
  EXPECT_EQ(draco.meshes.size(), plain.meshes.size());
  // The Draco export differs from the plain one; its accessors declare these decoded counts.
  EXPECT_EQ(draco.vertex_count(), 55887u);
  EXPECT_EQ(draco.triangle_count(), 65311u);
}

// Corrupts the Draco stream of bunny.glb: byte flips and truncation must end in a LoadError.
TEST(GltfDraco, CorruptStreamsAreRejected) {
  PENUMBRA_STABILITY("Draco streams with flipped bytes or truncated", "LoadError naming the file",
                     "-");
  const std::string bytes = test::read_bytes(test::shared_data() / "models" / "bunny.glb");
  ASSERT_GT(bytes.size(), 2000u);
  const std::size_t json_len =
      static_cast<unsigned char>(bytes[12]) | static_cast<unsigned char>(bytes[13]) << 8;
  const std::size_t bin = 20 + json_len + 8;  // the Draco bufferView starts the BIN chunk
  std::size_t rejected = 0;
  for (std::size_t i = 0; i < 64; ++i) {
    std::string bad = bytes;
    const std::size_t at = bin + (i * 7919) % 200;
    bad[at] = static_cast<char>(bad[at] ^ (1 + i % 255));
    try {
      load_gltf_from_memory({reinterpret_cast<const unsigned char*>(bad.data()), bad.size()},
                            "bunny");
    } catch (const LoadError& e) {
      ++rejected;
      EXPECT_EQ(e.file(), "bunny");
    }
  }
  std::printf("  %zu of 64 corrupted streams rejected, the rest decoded to valid meshes\n",
              rejected);
  std::string header_gone = bytes;
  for (std::size_t i = bin; i < bin + 8; ++i) header_gone[i] = 0;
  expect_load_error(
      [&] {
        load_gltf_from_memory(
            {reinterpret_cast<const unsigned char*>(header_gone.data()), header_gone.size()}, "b");
      },
      "b", "Draco decode failed");
}

}  // namespace
}  // namespace penumbra::assets
