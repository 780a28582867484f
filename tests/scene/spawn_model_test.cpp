#include "penumbra/scene/spawn_model.h"

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/assets/gltf.h"
#include "penumbra/assets/load_error.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/transform.h"
#include "test_support.h"

namespace penumbra::scene {
namespace {

using assets::gltf_to_engine;
using assets::load_gltf;
using assets::LoadError;
using assets::Model;
namespace test = assets::test;

using components::BaseColor;
using components::MeshInstance;
using components::Transform;

TEST(SpawnModel, BunnyBecomesOneEntity) {
  ecs::World world;
  const auto entities = load_gltf_into_world(test::shared_data() / "models" / "bunny.glb", world);
  ASSERT_EQ(entities.size(), 1u);
  EXPECT_EQ(world.size(), 1u);
  const auto* mesh = world.get<MeshInstance>(entities[0]);
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->mesh->positions.size(), 2826u);
  EXPECT_EQ(world.get<BaseColor>(entities[0])->rgba, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
  EXPECT_EQ(world.get<Transform>(entities[0])->world, gltf_to_engine());
}

TEST(SpawnModel, InstancesShareMeshDataAndQueriesSeeThem) {
  const Model model =
      load_gltf(test::assimp_gltf2() / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb");
  ecs::World world;
  const auto first = spawn_model(model, world);
  const auto second = spawn_model(model, world);
  ASSERT_EQ(first.size(), model.instances.size());
  EXPECT_EQ(world.size(), 2 * model.instances.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto* a = world.get<MeshInstance>(first[i]);
    const auto* b = world.get<MeshInstance>(second[i]);
    EXPECT_EQ(a->mesh.get(), b->mesh.get());
    EXPECT_EQ(a->mesh.get(), model.meshes[model.instances[i].mesh].get());
    EXPECT_EQ(world.get<Transform>(first[i])->world, model.instances[i].world);
  }
  std::size_t triangles = 0;
  world.query<const MeshInstance, const Transform>().each(
      [&](const MeshInstance& m, const Transform&) { triangles += m.mesh->indices.size() / 3; });
  EXPECT_EQ(
      triangles, 2 * [&] {
        std::size_t n = 0;
        for (const auto& inst : model.instances) n += model.meshes[inst.mesh]->indices.size() / 3;
        return n;
      }());
}

TEST(SpawnModel, FailedLoadLeavesTheWorldUnchanged) {
  PENUMBRA_STABILITY("a model that fails to load", "LoadError; the world unchanged", "-");
  ecs::World world;
  EXPECT_THROW(
      load_gltf_into_world(test::assimp_gltf2() / "RecursiveNodes" / "RecursiveNodes.gltf", world),
      LoadError);
  EXPECT_THROW(load_gltf_into_world("/nonexistent/model.glb", world), LoadError);
  EXPECT_EQ(world.size(), 0u);
}

}  // namespace
}  // namespace penumbra::scene
