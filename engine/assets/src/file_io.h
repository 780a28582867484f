// Internal: whole-file reads with LoadError messages ("no such file", "not a regular file",
// "empty file", "read failed").
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace penumbra::assets::detail {

inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 31;

std::vector<unsigned char> read_file(const std::filesystem::path& path);
// Throws LoadError unless `path` names an existing regular, non-empty file; returns its size.
std::uintmax_t require_file(const std::filesystem::path& path);

}  // namespace penumbra::assets::detail
