// OpenEXR loaders: HDR environment maps (RGB) and single-channel height maps.
//
// Contract: any channel type (half, float, uint) and compression OpenEXR 3.1 reads (DWAB
// included); the data window is the image, its first row is row 0. Values come back as linear
// float, unchanged; a NaN or infinite value is an error. Throws LoadError (file and reason) on
// a missing or unreadable file, a truncated or garbage file, missing channels, or an image
// larger than kMaxExrTexels. Threading: independent calls may run concurrently.
#pragma once

#include <cstddef>
#include <filesystem>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"

namespace penumbra::assets {

inline constexpr std::size_t kMaxExrTexels = std::size_t{1} << 28;

// Number of channels in the file's header (reads the header only).
int exr_channel_count(const std::filesystem::path& path);

// Channels R, G, B (A is ignored); a single luminance channel Y is repeated to grey. Row 0 is
// the top row of the image, the zenith of an equirectangular panorama (environment_map.h).
// Radiance is made non-negative: lossy DWA compression (8x8 DCT blocks) rings around the sun,
// and in ../shared/data/hdri the negative lobes hold up to 11% of a map's energy (sky.exr). Each
// negative value is set to 0 and the positive values of the same channel in its 8x8 block are
// scaled so the block's solid-angle-weighted sum is unchanged (zero if it was <= 0); counted in
// EnvironmentMap::clamped_values.
data::EnvironmentMap load_environment_map(const std::filesystem::path& path);

// Exactly one channel, whatever its name. Heights are min_elevation + elevation_scale * value,
// with the cell size from a JSON sidecar next to the file (heightmap.h), else 1 m and identity.
data::HeightField load_height_field_exr(const std::filesystem::path& path);

}  // namespace penumbra::assets
