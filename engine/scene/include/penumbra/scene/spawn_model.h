// glTF models into the ECS world (the one place where loaded assets meet the ECS): one entity per mesh instance (node x triangle primitive),
// with components::Transform, components::MeshInstance and components::BaseColor.
//
// Contract: meshes are shared (std::shared_ptr<const data::MeshData>), never copied per entity.
// Errors: load_gltf_into_world throws LoadError before touching the world, so a failed load
// leaves it unchanged. Threading: structural changes, so call with no system running
// (penumbra/ecs/world.h).
#pragma once

#include <filesystem>
#include <vector>

#include "penumbra/assets/gltf.h"
#include "penumbra/ecs/world.h"

namespace penumbra::scene {

// Entities created, in the order of model.instances.
std::vector<ecs::Entity> spawn_model(const assets::Model& model, ecs::World& world);

std::vector<ecs::Entity> load_gltf_into_world(const std::filesystem::path& path, ecs::World& world);

}  // namespace penumbra::scene
