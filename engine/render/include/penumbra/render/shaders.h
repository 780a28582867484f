// The renderer's shaders, compiled to SPIR-V at build time and embedded in the library.
//
// Why build time (glslangValidator via add_custom_command, engine/render/compile_shader.cmake)
// rather than run time with an on-disk cache: a GLSL error then stops the build with
// "<shader file>:<line>: <message>" before anything runs, the binaries carry their shaders (no
// path or cache to find, invalidate or race on between concurrent runs and tests), and the
// runtime needs neither glslang nor a writable directory. The cost is a rebuild to edit a
// shader, which the build does incrementally (each .glsl is a dependency of its outputs).
//
// Each file in shaders/ holds one pass; stages are selected with -DPENUMBRA_VERTEX /
// -DPENUMBRA_FRAGMENT (and variants with extra defines, e.g. DEBUG_SPHERES).
//
// Thread-safe (immutable data).
#pragma once

#include <cstdint>
#include <span>

#include "penumbra/render/resources.h"

namespace penumbra::render {

enum class Shader {
  kSkyVert,
  kSkyFrag,
  kTerrainVert,
  kTerrainFrag,
  kMeshVert,
  kMeshFrag,
  kDebugVert,
  kDebugSphereVert,
  kDebugFrag,
  kTonemapVert,
  kTonemapFrag,
  kMeshEnvVert,
  kMeshEnvFrag,
  kShadowVert,
  kShadowFrag,
  kCount
};

std::span<const std::uint32_t> shader_spirv(Shader shader);
// "terrain.glsl (vert)", for messages.
const char* shader_name(Shader shader);
// Throws VulkanError naming the shader when the driver rejects it.
Unique<VkShaderModule> create_shader_module(Device& device, Shader shader);

}  // namespace penumbra::render
