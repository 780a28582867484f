// glTF models into the ECS world (scene.h).
#include "penumbra/assets/scene.h"

#include "penumbra/components/mesh.h"
#include "penumbra/components/transform.h"

namespace penumbra::assets {

std::vector<ecs::Entity> spawn_model(const Model& model, ecs::World& world) {
  std::vector<ecs::Entity> entities;
  entities.reserve(model.instances.size());
  for (const Model::Instance& inst : model.instances) {
    const std::shared_ptr<const MeshData>& mesh = model.meshes.at(inst.mesh);
    entities.push_back(world.create_with(components::Transform{inst.world},
                                         components::MeshInstance{mesh},
                                         components::BaseColor{mesh->base_color}));
  }
  return entities;
}

std::vector<ecs::Entity> load_gltf_into_world(const std::filesystem::path& path,
                                              ecs::World& world) {
  const Model model = load_gltf(path);
  return spawn_model(model, world);
}

}  // namespace penumbra::assets
