// The checksum of the project's own binary files (sphere sets .psph, probe clouds .pcld).
// Threading: a pure function.
#pragma once

#include <cstdint>
#include <span>

namespace penumbra::assets {

// FNV-1a 64 (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
std::uint64_t fnv1a64(std::span<const unsigned char> bytes);

}  // namespace penumbra::assets
