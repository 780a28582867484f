// Procedural height fields: the dynamic test scenes of [Meier13] chapter 6
// (mountains, cones, sine grating, egg tray, city; the teddy scene is a scan, not generated).
//
// Contract: each generator samples a continuous function of world position (metres) on a
// resolution x resolution grid covering [0, extent]^2, so any resolution shows the same shape
// (cell_size = extent / (resolution - 1); chapter 6 renders every scene at 256x256). Heights
// are >= 0 and finite. Output depends only on the arguments: the same seed gives bit-identical
// heights. Throws std::invalid_argument on resolution < 2, a non-positive extent or
// resolution^2 > kMaxHeightSamples. Threading: pure functions.
#pragma once

#include <cstdint>
#include <string_view>

#include "penumbra/data/height_field.h"

namespace penumbra::assets {

struct TerrainGrid {
  int resolution = 256;   // samples per side
  float extent = 256.0f;  // metres per side
};

// Fractal Brownian motion of gradient noise, squared to sharpen peaks: heights in [0, height].
struct MountainParams {
  float height = 48.0f;       // metres at the fBm maximum
  float wavelength = 128.0f;  // metres, first octave
  int octaves = 8;
  float lacunarity = 2.0f;
  float gain = 0.5f;
  std::uint64_t seed = 1;
};

// Cones of different sizes evenly spaced on a circle about the centre ("cones v2" of 000
// section 6): cone i has base radius r_i from min_radius to max_radius and apex slope * r_i.
struct ConesParams {
  int count = 8;
  float ring_radius = 80.0f;
  float min_radius = 8.0f;
  float max_radius = 24.0f;
  float slope = 1.0f;  // apex height / base radius (45 degree flanks)
};

// h = amplitude/2 * (1 + sin(2 pi (x cos a + y sin a) / period)): parallel ridges.
struct SineGratingParams {
  float amplitude = 8.0f;  // peak to trough, metres
  float period = 32.0f;
  float angle = 0.0f;  // direction of the wave vector, radians from +x
};

// h = amplitude/2 * (1 + sin(2 pi x / period) sin(2 pi y / period)): bumps and cups.
struct EggTrayParams {
  float amplitude = 8.0f;
  float period = 32.0f;
};

// Street grid of square blocks, each split into lots x lots flat-roofed buildings with heights
// drawn per building from the seed, rounded to whole storeys.
struct CityParams {
  float block = 48.0f;   // block pitch, street included
  float street = 12.0f;  // street width
  float gap = 2.0f;      // between buildings in a block
  int lots = 2;
  float min_height = 6.0f;
  float max_height = 42.0f;
  float storey = 3.0f;
  std::uint64_t seed = 1;
};

data::HeightField fbm_mountains(const TerrainGrid& grid, const MountainParams& p = {});
data::HeightField cones(const TerrainGrid& grid, const ConesParams& p = {});
data::HeightField sine_grating(const TerrainGrid& grid, const SineGratingParams& p = {});
data::HeightField egg_tray(const TerrainGrid& grid, const EggTrayParams& p = {});
data::HeightField city_blocks(const TerrainGrid& grid, const CityParams& p = {});

// By name ("mountains", "cones", "sine_grating", "egg_tray", "city") with default parameters
// and `seed`; throws std::invalid_argument naming an unknown scene.
data::HeightField procedural_scene(std::string_view name, const TerrainGrid& grid,
                             std::uint64_t seed = 1);

}  // namespace penumbra::assets
