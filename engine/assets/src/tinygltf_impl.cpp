// The one translation unit that compiles tinygltf 2.7 (Debian's libtinygltf.so is built without
// Draco, and compiling it here puts it under the project's sanitizers). Images are not decoded
// (TINYGLTF_NO_STB_IMAGE, TINYGLTF_NO_EXTERNAL_IMAGE set for the whole library in
// CMakeLists.txt); Draco is decoded by gltf_draco.cpp, not by tinygltf's unchecked path.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
