// Horizon angles of a height field: for every sample (texel) and each of n_phi azimuths, the
// elevation of the highest terrain seen in that direction ([Meier13] eq. 4.2;
// for local lights, only terrain nearer than the light: eq. 4.22).
//
// Conventions shared by every horizon method (sweep, march, brute force):
//  - texel (x, y) is height sample (x, y) at plane position (x, y) * cell_size, height
//    height_scale * h(x, y) (assets/height_field.h);
//  - azimuth k is phi_k = 2 pi k / n_phi, measured from +x towards +y (the SH z-rotation and
//    equirect conventions of engine/sh);
//  - an angle is an elevation in radians: 0 is the horizontal plane, pi/2 the zenith. With
//    clamp_at_zero (environment light) it is >= 0: the terrain is taken to continue beyond its
//    border at no more than the receiver's height ([Meier13] sec. 4.2.1). Without (local lights) it
//    may be negative, and with no terrain in range it is -pi/2;
//  - the terrain ends at its border: nothing outside the grid occludes.
#pragma once

#include <cstddef>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "penumbra/data/height_field.h"

namespace penumbra::terrain_shadow {

// Half-open rectangle of texels [x0, x1) x [y0, y1).
struct TexelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 > x0 ? x1 - x0 : 0; }
  int height() const { return y1 > y0 ? y1 - y0 : 0; }
  bool empty() const { return width() == 0 || height() == 0; }
  std::size_t count() const { return static_cast<std::size_t>(width()) * height(); }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  static TexelRect all(const data::HeightField& f) { return {0, 0, f.width, f.height}; }
  bool operator==(const TexelRect&) const = default;  // the same corners
};

struct HorizonParams {
  int azimuths = 32;          // n_phi >= 3
  float height_scale = 1.0f;  // multiplies every height
  bool clamp_at_zero = true;  // environment: yes; local lights: no
  // Local lights ([Meier13] eq. 4.22): occluders farther from the receiver, in the plane, than this
  // point (plane position in metres, relative to sample (0, 0)) are ignored.
  std::optional<glm::vec2> limit_to_point;
};

// Storage on 64-byte (cache line) boundaries: the sweep writes whole lines of records with
// streaming stores (sweep_lanes.cpp, texel_records).
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{64}));
  }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete (p, std::align_val_t{64}); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept {
    return true;
  }
};

// n_phi angles per texel for a whole field; a method given a region writes only that region.
struct HorizonGrid {
  int width = 0, height = 0, azimuths = 0;
  std::vector<float, CacheLineAllocator<float>> angles;  // ((y * width) + x) * azimuths + k

  void resize(int w, int h, int n_phi) {
    width = w;
    height = h;
    azimuths = n_phi;
    angles.assign(static_cast<std::size_t>(w) * h * n_phi, 0.0f);
  }
  const float* texel(int x, int y) const {
    return angles.data() + (static_cast<std::size_t>(y) * width + x) * azimuths;
  }
  float* texel(int x, int y) {
    return angles.data() + (static_cast<std::size_t>(y) * width + x) * azimuths;
  }
};

// Throws std::invalid_argument naming the field (its `source`) for fewer than 2 x 2 samples, a
// cell size <= 0 or non-finite, a non-finite height or height_scale, fewer than 3 azimuths, or
// a region outside the field. Every horizon method calls it first.
void validate_horizon_input(const data::HeightField& field, const HorizonParams& params,
                            const TexelRect& region);
// Its parameter and region checks alone, for a width x height field called `name` (methods
// that see a derived structure rather than the field, e.g. the pyramid march).
void validate_horizon_params(const std::string& name, const HorizonParams& params, int width,
                             int height, const TexelRect& region);

}  // namespace penumbra::terrain_shadow
