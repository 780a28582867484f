// Sphere set files (.psph): a fitted sphere set (sphere_fit.h, ./penumbra spheres) with the fit
// method, its error figures and the source model, for the blocker accumulation system.
//
// Format, version 1, little-endian, no padding (44 + L + 20 n bytes):
//   offset  size  field
//   0       4     magic "PSPH"
//   4       4     u32 version (1)
//   8       4     u32 sphere count n (<= kMaxSphereFileSpheres)
//   12      4     u32 fit method (SphereFitMethod: 0 none, 1 k-means, 2 variational)
//   16      8     f64 outside volume ratio Er = vol(union of spheres) / vol(mesh) - 1 (>= -1)
//   24      8     f64 surface coverage (fraction of surface samples inside a sphere, [0, 1])
//   32      4     u32 source model name length L (<= kMaxSphereFileName), then L bytes (no NUL)
//   36 + L  20 n  per sphere: f32 centre x, y, z, f32 radius, i32 parent (-1 or another index)
//   end - 8 8     u64 FNV-1a 64 of every byte before it
// Contract: the reader rejects, with a LoadError naming the file and the reason, a missing or
// empty file, a wrong magic, another version, a truncated file or trailing bytes, a checksum
// mismatch, an unknown method, a non-finite or negative radius, a non-finite centre or figure,
// a coverage outside [0, 1], a parent out of range or a cyclic parent chain. The writer checks
// the same rules (std::invalid_argument) and writes atomically: a temporary file in the target's
// folder, renamed over the target, so a reader never sees a partial file.
// Threading: independent calls may run concurrently (not two writers of the same path).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "penumbra/assets/checksum.h"  // fnv1a64, the file's checksum
#include "penumbra/data/sphere_set.h"

namespace penumbra::assets {

enum class SphereFitMethod : std::uint32_t {
  kNone = 0,  // made by hand or by another tool
  kKMeans = 1,
  kVariational = 2,
};

// "none", "kmeans", "variational".
const char* sphere_fit_method_name(SphereFitMethod method);

inline constexpr std::uint32_t kSphereFileVersion = 1;
inline constexpr std::uint32_t kMaxSphereFileSpheres = 1u << 20;
inline constexpr std::uint32_t kMaxSphereFileName = 4096;

struct SphereSetFile {
  std::vector<data::Sphere> spheres;
  SphereFitMethod method = SphereFitMethod::kNone;
  double outside_volume_ratio = 0;  // Er
  double coverage = 1;
  std::string source_model;  // the fitted model's file name
};

// The bytes of a version-1 file (checksum included). Throws std::invalid_argument on data the
// reader would reject.
std::vector<unsigned char> encode_sphere_file(const SphereSetFile& set);

// Parses a whole file's bytes; `name` is used in messages. Throws LoadError.
SphereSetFile parse_sphere_file(std::span<const unsigned char> bytes, const std::string& name);

SphereSetFile load_sphere_file(const std::filesystem::path& path);

// Atomic write (see above). Throws std::invalid_argument on bad data, std::runtime_error
// naming the file when it cannot be written; on failure no temporary file is left behind.
void write_sphere_file(const std::filesystem::path& path, const SphereSetFile& set);

}  // namespace penumbra::assets
