// Internal: whole-file reads with LoadError messages ("no such file", "not a regular file",
// "empty file", "read failed"), and atomic whole-file writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace penumbra::assets::detail {

inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 31;

std::vector<unsigned char> read_file(const std::filesystem::path& path);
// Throws LoadError unless `path` names an existing regular, non-empty file; returns its size.
std::uintmax_t require_file(const std::filesystem::path& path);

// Writes `bytes` to a temporary file in `path`'s folder (so the rename never crosses file
// systems), flushes it to disk and renames it over `path`: a reader sees the old file or the
// new one, never a partial one. Throws std::runtime_error naming `path` and the cause; on
// failure the temporary file is removed and an existing `path` is left as it was.
// Threading: not two writers of the same path at once.
void write_file_atomic(const std::filesystem::path& path, std::span<const unsigned char> bytes);

}  // namespace penumbra::assets::detail
