// Internal: little-endian fields of the project's binary files (sphere_file.cpp,
// probe_cloud_file.cpp). Writes go into a buffer sized up front; reads are unchecked (the caller
// has checked the size).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace penumbra::assets::detail {

// Both formats end in an FNV-1a 64-bit checksum of every byte before it.
inline constexpr std::size_t kChecksumBytes = 8;

struct ByteWriter {
  std::vector<unsigned char>& out;
  std::size_t at = 0;
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out[at++] = static_cast<unsigned char>(v >> (8 * i));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out[at++] = static_cast<unsigned char>(v >> (8 * i));
  }
  void i32(std::int32_t v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void bytes(const void* p, std::size_t n) {
    if (n > 0) std::memcpy(out.data() + at, p, n);
    at += n;
  }
};

inline std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t{p[i]} << (8 * i);
  return v;
}
inline std::uint64_t get_u64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= std::uint64_t{p[i]} << (8 * i);
  return v;
}
inline std::int32_t get_i32(const unsigned char* p) {
  return std::bit_cast<std::int32_t>(get_u32(p));
}
inline float get_f32(const unsigned char* p) {
  return std::bit_cast<float>(get_u32(p));
}

}  // namespace penumbra::assets::detail
