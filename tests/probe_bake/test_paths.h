// Where the probe bake tests find the repository and the shared data (one definition, so that a
// unity build of the test target sees one).
#pragma once

#include <filesystem>

namespace penumbra::probe_bake {

inline const std::filesystem::path kRoot = PENUMBRA_SOURCE_DIR;
inline const std::filesystem::path kData = kRoot / ".." / "shared" / "data";

}  // namespace penumbra::probe_bake
