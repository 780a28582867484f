#include "penumbra/assets/mesh_simplify.h"

#include <stdexcept>
#include <string>

#include <meshoptimizer.h>

namespace penumbra::assets {

SimplifiedMesh simplify_mesh(const data::MeshData& mesh, const SimplifyOptions& options) {
  const std::string name = "mesh '" + mesh.name + "'";
  if (mesh.indices.size() < 3 || mesh.indices.size() % 3 != 0)
    throw std::invalid_argument(name + ": no triangles to simplify");
  for (const std::uint32_t i : mesh.indices)
    if (i >= mesh.positions.size())
      throw std::invalid_argument(name + ": index " + std::to_string(i) + " out of range");
  if (!(options.target_ratio > 0 && options.target_ratio <= 1))
    throw std::invalid_argument(name + ": target ratio " + std::to_string(options.target_ratio) +
                                " must be in (0, 1]");
  if (!(options.max_error >= 0)) throw std::invalid_argument(name + ": max error must be >= 0");

  const std::size_t target = static_cast<std::size_t>(static_cast<double>(mesh.indices.size() / 3) *
                                                      options.target_ratio) *
                             3;
  std::vector<std::uint32_t> indices(mesh.indices.size());
  float error = 0;
  indices.resize(meshopt_simplify(indices.data(), mesh.indices.data(), mesh.indices.size(),
                                  &mesh.positions[0].x, mesh.positions.size(), sizeof(glm::vec3),
                                  std::max<std::size_t>(target, 3), options.max_error, 0, &error));

  // Only the vertices still used, in first-use order.
  std::vector<unsigned int> remap(mesh.positions.size());
  const std::size_t kept = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(),
                                                            indices.size(), mesh.positions.size());
  SimplifiedMesh out;
  out.error = error;
  out.mesh.name = mesh.name;
  out.mesh.base_color = mesh.base_color;
  out.mesh.indices.resize(indices.size());
  meshopt_remapIndexBuffer(out.mesh.indices.data(), indices.data(), indices.size(), remap.data());
  out.mesh.positions.resize(kept);
  meshopt_remapVertexBuffer(out.mesh.positions.data(), mesh.positions.data(), mesh.positions.size(),
                            sizeof(glm::vec3), remap.data());
  if (mesh.normals.size() == mesh.positions.size()) {
    out.mesh.normals.resize(kept);
    meshopt_remapVertexBuffer(out.mesh.normals.data(), mesh.normals.data(), mesh.normals.size(),
                              sizeof(glm::vec3), remap.data());
  }
  return out;
}

}  // namespace penumbra::assets
