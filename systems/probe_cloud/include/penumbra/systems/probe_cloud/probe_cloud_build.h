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
  // Coordinates closer than this fraction of the bounding box's shortest side to one of the box's
  // faces are moved onto it, so that a grid's outer layer moved by a hair keeps flat hull faces
  // (snap_to_box_faces below); 0, a negative value or NaN moves none.
  float face_snap = 1e-4f;
};

struct ProbeCloudBuildReport {
  std::size_t input_points = 0, merged_duplicates = 0, tetrahedra = 0, outer_cells = 0;
  std::size_t snapped_coordinates = 0;    // coordinates face_snap moved onto the box's faces
  std::vector<std::uint32_t> kept_index;  // per input point: the probe it became (after merging)
  double seconds = 0;                     // wall time of the build
};

// Moves every coordinate of `positions` that lies within `relative` times the bounding box's
// shortest side of one of the box's faces onto that face (a flat box moves nothing); returns how
// many coordinates moved. Why: the hull of a grid whose outer layer is off its planes by a hair
// (rounding, another compiler, a validity move) is not its flat faces' small triangles but long
// slivers across the whole face, and the outer cells on them extrapolate one side of a wall onto
// the other (docs/probe_cloud.md, "Nearly flat hull faces"). Faces that are flat but not
// axis-aligned are not helped.
std::size_t snap_to_box_faces(std::span<glm::vec3> positions, double relative);

// Tetrahedralizes `positions` into a cloud with the given SH (probe-major, 3 * bands^2 floats
// per point; empty = zeros). Coordinates near the bounding box's faces are moved onto them first
// (ProbeCloudBuildSettings::face_snap); the cloud's positions are the moved ones. Throws
// std::invalid_argument naming the index for NaN/inf positions or a wrong sh size or bands. Probes
// closer than merge_distance to an earlier kept probe are merged into it (it keeps its position;
// its SH becomes the mean of the merged probes); 0 merges exact duplicates only. 0-3 probes, or all
// coplanar/collinear: a cloud with the probes, their SH and zero hull normals but no cells
// (inner_count == 0).
data::ProbeCloud build_probe_cloud(std::span<const glm::vec3> positions, std::span<const float> sh,
                                   const ProbeCloudBuildSettings& settings = {},
                                   ProbeCloudBuildReport* report = nullptr);

// The per-cell transform of data/probe_cloud.h for cell `cell` of `cloud` (needs positions,
// cells and, for outer cells, hull_normals). build_probe_cloud and the validation use it.
glm::mat4 probe_cell_transform(const data::ProbeCloud& cloud, std::uint32_t cell);

}  // namespace penumbra::probe_cloud
