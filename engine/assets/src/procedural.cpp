// Procedural height fields (procedural.h): the test scenes of [Meier13]
// chapter 6. The thesis shows the scenes but gives no formulas; the shapes and defaults here
// are ours, sized for its 256x256 grids.
#include "penumbra/assets/procedural.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "penumbra/assets/heightmap.h"

namespace penumbra::assets {
namespace {

std::uint64_t mix(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

std::uint64_t hash(std::uint64_t seed, std::int64_t a, std::int64_t b) {
  return mix(mix(mix(seed) ^ static_cast<std::uint64_t>(a)) ^ static_cast<std::uint64_t>(b));
}

// Uniform in [0, 1) from the top 24 bits.
float unit(std::uint64_t h) {
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);
}

// 2D gradient noise (Perlin 2002: quintic fade, gradients from a fixed set of 8), about [-1, 1].
float gradient_noise(float x, float y, std::uint64_t seed) {
  static constexpr float kG[8][2] = {{1, 0},
                                     {-1, 0},
                                     {0, 1},
                                     {0, -1},
                                     {0.70710678f, 0.70710678f},
                                     {-0.70710678f, 0.70710678f},
                                     {0.70710678f, -0.70710678f},
                                     {-0.70710678f, -0.70710678f}};
  const float fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const float tx = x - fx, ty = y - fy;
  auto corner = [&](std::int64_t dx, std::int64_t dy) {
    const float* g = kG[hash(seed, ix + dx, iy + dy) & 7];
    return g[0] * (tx - static_cast<float>(dx)) + g[1] * (ty - static_cast<float>(dy));
  };
  auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const float u = fade(tx), v = fade(ty);
  const float a = corner(0, 0) + u * (corner(1, 0) - corner(0, 0));
  const float b = corner(0, 1) + u * (corner(1, 1) - corner(0, 1));
  return std::numbers::sqrt2_v<float> * (a + v * (b - a));
}

template <class F>
data::HeightField sample(const TerrainGrid& grid, const std::string& source, F&& f) {
  if (grid.resolution < 2 || !(grid.extent > 0) || !std::isfinite(grid.extent) ||
      static_cast<std::size_t>(grid.resolution) * grid.resolution > kMaxHeightSamples)
    throw std::invalid_argument("procedural " + source + ": bad grid (resolution " +
                                std::to_string(grid.resolution) + ", extent " +
                                std::to_string(grid.extent) + ")");
  data::HeightField hf;
  hf.width = hf.height = grid.resolution;
  hf.cell_size = grid.extent / static_cast<float>(grid.resolution - 1);
  hf.source = "procedural:" + source;
  hf.heights.resize(static_cast<std::size_t>(grid.resolution) * grid.resolution);
  for (int y = 0; y < grid.resolution; ++y)
    for (int x = 0; x < grid.resolution; ++x)
      hf.at(x, y) = std::max(
          0.0f, f(static_cast<float>(x) * hf.cell_size, static_cast<float>(y) * hf.cell_size));
  return hf;
}

}  // namespace

data::HeightField fbm_mountains(const TerrainGrid& grid, const MountainParams& p) {
  if (p.octaves < 1 || p.octaves > 24 || !(p.wavelength > 0))
    throw std::invalid_argument("procedural mountains: octaves must be 1..24 and wavelength > 0");
  float norm = 0, amp = 1;
  for (int o = 0; o < p.octaves; ++o, amp *= p.gain) norm += amp;
  return sample(grid, "mountains seed=" + std::to_string(p.seed), [&](float x, float y) {
    float sum = 0, a = 1, freq = 1 / p.wavelength;
    for (int o = 0; o < p.octaves; ++o, a *= p.gain, freq *= p.lacunarity) {
      const float off = 1000.0f * unit(hash(p.seed, o, 7));  // decorrelates the octaves' lattices
      sum += a *
             gradient_noise(x * freq + off, y * freq + off, p.seed + static_cast<std::uint64_t>(o));
    }
    const float t = std::clamp(0.5f + 0.5f * sum / norm, 0.0f, 1.0f);
    return p.height * t * t;
  });
}

data::HeightField cones(const TerrainGrid& grid, const ConesParams& p) {
  if (p.count < 1 || !(p.min_radius > 0) || p.max_radius < p.min_radius)
    throw std::invalid_argument(
        "procedural cones: need count >= 1 and 0 < min_radius <= max_radius");
  const float c = grid.extent / 2;
  return sample(grid, "cones", [&](float x, float y) {
    float h = 0;
    for (int i = 0; i < p.count; ++i) {
      const float a =
          2 * std::numbers::pi_v<float> * static_cast<float>(i) / static_cast<float>(p.count);
      const float t = p.count > 1 ? static_cast<float>(i) / static_cast<float>(p.count - 1) : 0.0f;
      const float r = p.min_radius + t * (p.max_radius - p.min_radius);
      const float d =
          std::hypot(x - (c + p.ring_radius * std::cos(a)), y - (c + p.ring_radius * std::sin(a)));
      h = std::max(h, p.slope * (r - d));
    }
    return h;
  });
}

data::HeightField sine_grating(const TerrainGrid& grid, const SineGratingParams& p) {
  if (!(p.period > 0)) throw std::invalid_argument("procedural sine grating: period must be > 0");
  const float kx = std::cos(p.angle), ky = std::sin(p.angle),
              w = 2 * std::numbers::pi_v<float> / p.period;
  return sample(grid, "sine_grating", [&](float x, float y) {
    return 0.5f * p.amplitude * (1 + std::sin(w * (kx * x + ky * y)));
  });
}

data::HeightField egg_tray(const TerrainGrid& grid, const EggTrayParams& p) {
  if (!(p.period > 0)) throw std::invalid_argument("procedural egg tray: period must be > 0");
  const float w = 2 * std::numbers::pi_v<float> / p.period;
  return sample(grid, "egg_tray", [&](float x, float y) {
    return 0.5f * p.amplitude * (1 + std::sin(w * x) * std::sin(w * y));
  });
}

data::HeightField city_blocks(const TerrainGrid& grid, const CityParams& p) {
  if (p.lots < 1 || !(p.block > p.street) || p.street < 0 || p.gap < 0 || !(p.storey > 0) ||
      p.max_height < p.min_height)
    throw std::invalid_argument("procedural city: need block > street >= 0, lots >= 1, storey > 0");
  const float inner = p.block - p.street, lot = inner / static_cast<float>(p.lots);
  return sample(grid, "city seed=" + std::to_string(p.seed), [&](float x, float y) {
    // Blocks start half a street from the origin; streets run between them.
    const float bx = x - 0.5f * p.street, by = y - 0.5f * p.street;
    const float fx = std::floor(bx / p.block), fy = std::floor(by / p.block);
    const float ux = bx - fx * p.block, uy = by - fy * p.block;  // inside the block pitch
    if (ux >= inner || uy >= inner) return 0.0f;                 // street
    const float lx = std::floor(ux / lot), ly = std::floor(uy / lot);
    const float half_gap = 0.5f * p.gap;
    const float ox = ux - lx * lot, oy = uy - ly * lot;
    if (ox < half_gap || oy < half_gap || ox > lot - half_gap || oy > lot - half_gap) return 0.0f;
    const auto gx = static_cast<std::int64_t>(fx) * p.lots + static_cast<std::int64_t>(lx);
    const auto gy = static_cast<std::int64_t>(fy) * p.lots + static_cast<std::int64_t>(ly);
    const float h = p.min_height + unit(hash(p.seed, gx, gy)) * (p.max_height - p.min_height);
    return std::max(p.storey, std::round(h / p.storey) * p.storey);
  });
}

data::HeightField procedural_scene(std::string_view name, const TerrainGrid& grid, std::uint64_t seed) {
  if (name == "mountains") {
    MountainParams p;
    p.seed = seed;
    return fbm_mountains(grid, p);
  }
  if (name == "cones") return cones(grid);
  if (name == "sine_grating") return sine_grating(grid);
  if (name == "egg_tray") return egg_tray(grid);
  if (name == "city") {
    CityParams p;
    p.seed = seed;
    return city_blocks(grid, p);
  }
  throw std::invalid_argument("unknown procedural scene \"" + std::string(name) +
                              "\" (mountains, cones, sine_grating, egg_tray, city)");
}

}  // namespace penumbra::assets
