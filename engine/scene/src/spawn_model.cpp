// glTF models into the ECS world (spawn_model.h).
#include "penumbra/scene/spawn_model.h"

#include "penumbra/components/mesh.h"
#include "penumbra/components/transform.h"

namespace penumbra::scene {

std::vector<ecs::Entity> spawn_model(const assets::Model& model, ecs::World& world) {
  std::vector<ecs::Entity> entities;
  entities.reserve(model.instances.size());
  for (const assets::Model::Instance& inst : model.instances) {
    const std::shared_ptr<const data::MeshData>& mesh = model.meshes.at(inst.mesh);
    entities.push_back(world.create_with(components::Transform{inst.world},
                                         components::MeshInstance{mesh},
                                         components::BaseColor{mesh->base_color}));
  }
  return entities;
}

std::vector<ecs::Entity> load_gltf_into_world(const std::filesystem::path& path,
                                              ecs::World& world) {
  const assets::Model model = assets::load_gltf(path);
  return spawn_model(model, world);
}

}  // namespace penumbra::scene
