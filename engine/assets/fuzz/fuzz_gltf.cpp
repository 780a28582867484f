// libFuzzer target: glTF/GLB from memory (gltf.h): our GLB container pre-pass, tinygltf's
// parser, our validation and Draco decoding. External files are refused. See README.md.
#include <cstddef>
#include <cstdint>

#include "penumbra/assets/gltf.h"
#include "penumbra/assets/load_error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra::assets;
  try {
    const Model m = load_gltf_from_memory({data, size}, "fuzz.glb");
    for (const Model::Instance& inst : m.instances)
      if (inst.mesh >= m.meshes.size()) __builtin_trap();
    for (const auto& mesh : m.meshes)
      for (std::uint32_t i : mesh->indices)
        if (i >= mesh->positions.size()) __builtin_trap();
  } catch (const LoadError&) {
  }
  return 0;
}
