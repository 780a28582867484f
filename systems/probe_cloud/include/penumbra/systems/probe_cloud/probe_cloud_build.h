// Builds a data::ProbeCloud from probe positions and SH: merges duplicates, tetrahedralizes
// (delaunay_tetrahedralization.h), adds the outer cells on the hull ([Cupisz12]), the hull
// normals and the per-cell transforms ([Sukys14] sec. 4.2). See docs/probe_cloud.md.
// Threading: a pure function; no shared state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/probe_cloud.h"

namespace penumbra::probe_cloud {

struct ProbeCloudBuildSettings {
  int bands = data::kProbeDefaultBands;  // SH bands of the given sh (2..4)
  float merge_distance = 1e-3f;          // metres: probes closer than this are merged (duplicates)
};

struct ProbeCloudBuildReport {
  std::size_t input_points = 0, merged_duplicates = 0, tetrahedra = 0, outer_cells = 0;
  std::vector<std::uint32_t> kept_index;  // per input point: the probe it became (after merging)
  double seconds = 0;                     // wall time of the build
};

// Tetrahedralizes `positions` into a cloud with the given SH (probe-major, 3 * bands^2 floats
// per point; empty = zeros). Throws std::invalid_argument naming the index for NaN/inf positions
// or a wrong sh size or bands. Probes closer than merge_distance to an earlier kept probe are
// merged into it (it keeps its position; its SH becomes the mean of the merged probes); 0 merges
// exact duplicates only. 0-3 probes, or all coplanar/collinear: a cloud with the probes, their SH
// and zero hull normals but no cells (inner_count == 0).
data::ProbeCloud build_probe_cloud(std::span<const glm::vec3> positions, std::span<const float> sh,
                                   const ProbeCloudBuildSettings& settings = {},
                                   ProbeCloudBuildReport* report = nullptr);

// The per-cell transform of data/probe_cloud.h for cell `cell` of `cloud` (needs positions,
// cells and, for outer cells, hull_normals). build_probe_cloud and the validation use it.
glm::mat4 probe_cell_transform(const data::ProbeCloud& cloud, std::uint32_t cell);

}  // namespace penumbra::probe_cloud
