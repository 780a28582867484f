// Atomic whole-file writes, for every file format the project writes (sphere sets, probe
// clouds, settings, input recordings).
// Threading: not two writers of the same path at once.
#pragma once

#include <filesystem>
#include <span>
#include <string_view>

namespace penumbra::assets {

// Writes `bytes` to a temporary file in `path`'s folder (so the rename never crosses file
// systems), flushes it to disk and renames it over `path`: a reader sees the old file or the
// new one, never a partial one. Throws std::runtime_error naming `path` and the cause; on
// failure the temporary file is removed and an existing `path` is left as it was.
void write_file_atomic(const std::filesystem::path& path, std::span<const unsigned char> bytes);
inline void write_file_atomic(const std::filesystem::path& path, std::string_view text) {
  write_file_atomic(path, {reinterpret_cast<const unsigned char*>(text.data()), text.size()});
}

}  // namespace penumbra::assets
