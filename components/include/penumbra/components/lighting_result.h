// Lighting results the renderer shows, written by the lighting systems: per-vertex lighting of
// a mesh (with MeshInstance) and per-texel lighting of a terrain (with Terrain). Linear
// RGB; the shaded colour is albedo * lighting.
//
// The arrays are shared and immutable once published: a system that recomputes lighting
// publishes a new vector, so the render packet can share it without a copy while the next
// frame's systems run (see penumbra/render/packet.h).
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::components {

// One value per position of the entity's MeshInstance.
struct VertexLighting {
  std::shared_ptr<const std::vector<glm::vec3>> rgb;
};

// width * height values, row-major; texel centres on the terrain's grid (render/packet.h).
// Later systems modulate the terrain system's lighting (the blockers' shadows, the spherical
// lights' bounce) and publish the result in `rgb`; `composed` stays the terrain system's own
// array, so each of them can start again from it instead of from its own last output.
struct TerrainLighting {
  std::shared_ptr<const std::vector<glm::vec3>> rgb;
  int width = 0;
  int height = 0;
  std::shared_ptr<const std::vector<glm::vec3>> composed;  // terrain_shadow.compose's, or null
};

}  // namespace penumbra::components
