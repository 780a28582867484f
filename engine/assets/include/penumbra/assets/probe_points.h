// Probe point files: a text list of probe positions, each optionally with its irradiance SH, the
// input of ./penumbra tetra (engine/assets/tools/penumbra_tetra.cpp).
//
// Format: one probe per line, whitespace-separated numbers: `x y z` (metres), optionally
// followed by 3 b^2 SH coefficients for b bands (channel r, g, b, then coefficient, as
// data::ProbeCloud::sh). Either every probe line carries SH or none does. `#` starts a comment
// to the end of the line; blank lines are skipped; "\r\n" line ends are accepted.
// Contract: a malformed line (a token that is not a number, a value count other than 3 or
// 3 + 3 b^2, SH on some lines only, a NaN or infinite value) or more than
// kMaxProbeCloudProbes points is rejected with a LoadError naming the file, the line number
// (from 1) and the reason; a missing or empty file as file_io.h does. A file with comments
// only gives no points. Threading: independent calls may run concurrently.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::assets {

struct ProbePoints {
  std::vector<glm::vec3> positions;
  std::vector<float> sh;  // empty (no SH in the file) or 3 b^2 per position, probe-major
};

// `bands` (2..4, else std::invalid_argument) sets how many SH values a line may carry.
ProbePoints parse_probe_points(std::string_view text, int bands, const std::string& name);
ProbePoints load_probe_points(const std::filesystem::path& path, int bands);

}  // namespace penumbra::assets
