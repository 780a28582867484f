// Probe cloud files (.pcld): a tetrahedralized irradiance probe cloud (data/probe_cloud.h),
// written by ./penumbra tetra (and later the baker), read by the probe-cloud traversal system
// and ./penumbra info.
//
// Format, version 1, little-endian, no padding; n probes, c cells, b bands
// (32 + n (24 + 12 b^2) + 96 c bytes):
//   offset         size        field
//   0              4           magic "PCLD"
//   4              4           u32 version (1)
//   8              4           u32 bands b (kProbeMinBands..kProbeMaxBands: 2..4)
//   12             4           u32 probe count n (<= kMaxProbeCloudProbes)
//   16             4           u32 cell count c (<= kMaxProbeCloudCells)
//   20             4           u32 inner count (<= c): cells [0, inner) are inner tetrahedra
//   24             12 n        positions: f32 x, y, z per probe
//   24 + 12 n      12 b^2 n    SH: f32, probe-major, then channel r, g, b, then coefficient
//   A = 24 + (12 + 12 b^2) n
//   A              12 n        hull normals: f32 x, y, z per probe
//   A + 12 n       32 c        cells: i32 vertices[4], i32 neighbours[4]
//   A + 12 n + 32 c  64 c      transforms: 16 f32 per cell, column-major (glm::mat4 order)
//   end - 8        8           u64 FNV-1a 64 (checksum.h) of every byte before it
// Contract: the reader rejects, with a LoadError naming the file and the reason, a missing or
// empty file, a wrong magic ("not a probe cloud file"), another version, a truncated file or
// trailing bytes, a checksum mismatch, bands outside 2..4, counts above the caps below or an
// inner count above the cell count, a non-finite position, SH coefficient, hull normal or
// transform entry, a vertex index outside [0, n) (an outer cell's vertices[3] must be
// data::kOuterVertex), a neighbour index outside [0, c), an outer cell among the inner ones or
// an inner tetrahedron after the outer cells. It does not check geometry or topology
// (orientation, neighbour symmetry, the Delaunay property, hull cover): that is
// probe_cloud::validate_probe_cloud (systems/probe_cloud). The writer checks the same rules
// plus the array sizes (std::invalid_argument) and writes atomically: a temporary file in the
// target's folder, renamed over the target, so a reader never sees a partial file.
// Threading: independent calls may run concurrently (not two writers of the same path).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "penumbra/assets/checksum.h"
#include "penumbra/data/probe_cloud.h"

namespace penumbra::assets {

inline constexpr std::uint32_t kProbeCloudFileVersion = 1;
// Caps: 16.8 M probes, 134 M cells (8 per probe; a Delaunay tetrahedralization has about 6.5).
// Both keep every index within i32. The loader's 2 GiB file limit (file_io.h) is reached first
// in practice (about 2.8 M probes at 3 bands and 6.5 cells per probe).
inline constexpr std::uint32_t kMaxProbeCloudProbes = 1u << 24;
inline constexpr std::uint32_t kMaxProbeCloudCells = 1u << 27;

// The size in bytes of a version-1 file with these counts.
std::uint64_t probe_cloud_file_size(int bands, std::uint64_t probes, std::uint64_t cells);

// The bytes of a version-1 file (checksum included). Throws std::invalid_argument on a cloud
// the reader would reject or whose arrays disagree in size (sh: 3 b^2 per probe, hull_normals:
// one per probe, transforms: one per cell).
std::vector<unsigned char> encode_probe_cloud_file(const data::ProbeCloud& cloud);

// Parses a whole file's bytes; `name` is used in messages. Throws LoadError.
data::ProbeCloud parse_probe_cloud_file(std::span<const unsigned char> bytes,
                                        const std::string& name);

// Reads and parses `path`. Throws LoadError.
data::ProbeCloud load_probe_cloud_file(const std::filesystem::path& path);

// Atomic write (see above). Throws std::invalid_argument on bad data (nothing written),
// std::runtime_error naming the file when it cannot be written; on failure no temporary file
// is left behind and an existing file at `path` is unchanged.
void save_probe_cloud_file(const std::filesystem::path& path, const data::ProbeCloud& cloud);

}  // namespace penumbra::assets
