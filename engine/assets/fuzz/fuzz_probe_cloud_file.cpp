// libFuzzer target: the probe cloud file reader (probe_cloud_file.h). See README.md.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "penumbra/assets/load_error.h"
#include "penumbra/assets/probe_cloud_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra;
  try {
    const data::ProbeCloud c = assets::parse_probe_cloud_file({data, size}, "fuzz.pcld");
    // What the reader promises: bands in range, array sizes that agree, finite values, every
    // index in range, inner cells first, and the bytes re-encode to the very input.
    if (c.bands < data::kProbeMinBands || c.bands > data::kProbeMaxBands) __builtin_trap();
    const std::size_t n = c.probe_count();
    if (c.sh.size() != n * c.coeffs_per_probe() || c.hull_normals.size() != n ||
        c.transforms.size() != c.cells.size() || c.inner_count > c.cells.size())
      __builtin_trap();
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(c.positions[i][k]) || !std::isfinite(c.hull_normals[i][k]))
          __builtin_trap();
    for (float f : c.sh)
      if (!std::isfinite(f)) __builtin_trap();
    const auto cells = static_cast<std::int64_t>(c.cells.size());
    for (std::size_t i = 0; i < c.cells.size(); ++i) {
      const data::ProbeCell& cell = c.cells[i];
      if (cell.outer() != (i >= c.inner_count)) __builtin_trap();
      for (int k = 0; k < (cell.outer() ? 3 : 4); ++k) {
        const std::int32_t v = cell.vertices[static_cast<std::size_t>(k)];
        if (v < 0 || static_cast<std::size_t>(v) >= n) __builtin_trap();
      }
      for (std::int32_t nb : cell.neighbours)
        if (nb < 0 || nb >= cells) __builtin_trap();
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row)
          if (!std::isfinite(c.transforms[i][col][row])) __builtin_trap();
    }
    const auto again = assets::encode_probe_cloud_file(c);
    if (again.size() != size) __builtin_trap();
    for (std::size_t i = 0; i < size; ++i)
      if (again[i] != data[i]) __builtin_trap();
  } catch (const assets::LoadError&) {
  }
  return 0;
}
