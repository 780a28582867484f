// Internal: whole-file reads with LoadError messages ("no such file", "not a regular file",
// "empty file", "read failed"); atomic whole-file writes are public (atomic_write.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "penumbra/assets/atomic_write.h"

namespace penumbra::assets::detail {

inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 31;

std::vector<unsigned char> read_file(const std::filesystem::path& path);
// Throws LoadError unless `path` names an existing regular, non-empty file; returns its size.
std::uintmax_t require_file(const std::filesystem::path& path);

using assets::write_file_atomic;  // penumbra/assets/atomic_write.h

}  // namespace penumbra::assets::detail
