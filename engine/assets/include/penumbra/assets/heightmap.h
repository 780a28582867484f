// Height maps from files: 16-bit binary PGM and single-channel OpenEXR, each with an optional
// JSON sidecar (same path, extension .json).
//
// PGM: the Netpbm P5 format (netpbm.sourceforge.net/doc/pgm.html): "P5", width, height and
// maxval as ASCII decimals separated by whitespace, '#' comments to the end of a line allowed
// anywhere before maxval, one whitespace byte, then width*height samples, row by row, one byte
// each when maxval < 256, else two bytes big-endian. Every sample must be <= maxval and the file
// must end after the last sample (trailing bytes mean the header's dimensions are wrong).
//
// Sidecar fields (all optional; ../shared/data/terrain/jacksboro_fault_dem.json is an example):
//   width, height        must match the image
//   min_elevation        metres added to every sample (default 0)
//   elevation_scale      metres per sample unit (default 1: "value = elevation - min_elevation")
//   max_elevation        every height must be <= it (a consistency check)
//   cell_size_m          metres between samples, or
//   suggested_cell_size_m [x, y], or cell_size_x / cell_size_y when cell_size_units is metres.
// A HeightField has square cells; when x and y spacing differ the loader resamples the coarser
// axis linearly to the finer spacing (the DEM: 403x344 at 74.4 x 92.6 m -> 403x427 at 74.4 m;
// interpolation between rows trims extremes: 236..1076 m becomes 240.7..1073.5 m).
//
// Errors: LoadError naming the file (or the sidecar) and the reason. Threading: independent
// calls may run concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/data/height_field.h"

namespace penumbra::assets {

inline constexpr std::size_t kMaxHeightSamples = std::size_t{1} << 28;

struct PgmImage {
  int width = 0;
  int height = 0;
  int maxval = 0;
  std::vector<std::uint16_t> samples;  // width * height, row-major
};

// Parses a whole P5 file held in memory; `name` is used in error messages.
PgmImage parse_pgm(std::span<const unsigned char> bytes, const std::string& name);

struct HeightSidecar {
  std::optional<int> width, height;
  double min_elevation = 0;
  double elevation_scale = 1;
  std::optional<double> max_elevation;
  std::optional<double> cell_size_x, cell_size_y;  // metres
};

// Parses sidecar JSON text; `name` is used in error messages.
HeightSidecar parse_height_sidecar(std::string_view json, const std::string& name);

// Applies a sidecar to samples: checks dimensions, maps values to metres, rejects NaN/inf and
// heights above max_elevation, resamples to square cells. `name` is used in error messages.
data::HeightField make_height_field(int width, int height, std::span<const float> values,
                              const HeightSidecar& sidecar, const std::string& name);

// Reads "<path without extension>.json" if it exists (empty sidecar otherwise).
HeightSidecar load_height_sidecar(const std::filesystem::path& image_path);

// A .pgm file and its sidecar.
data::HeightField load_height_field_pgm(const std::filesystem::path& path);

// By extension: .pgm or .exr (load_height_field_exr in exr.h).
data::HeightField load_height_field(const std::filesystem::path& path);

}  // namespace penumbra::assets
