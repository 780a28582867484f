// Internal: the geometry of one azimuth shared by the line sweep and the brute-force ray march,
// so that both sample the terrain at bit-identical points (horizon_sweep.h).
#pragma once

#include <cmath>
#include <cstddef>

#include "penumbra/data/height_field.h"

namespace penumbra::terrain_shadow::detail {

// Azimuth phi seen in (major, minor) coordinates: the major axis is the one the direction moves
// along faster. Positions are (u, b): u = major coordinate (integer on sample lines), b = minor.
struct AzimuthFrame {
  bool x_major = true;
  int step = 1;               // +1 or -1: sign of the direction's major component
  double slope = 0;           // d minor / d major (|slope| <= 1), snapped to -1, 0, 1 when close
  float metres_per_step = 1;  // plane distance of one major step
  int major_size = 0, minor_size = 0;

  AzimuthFrame(const data::HeightField& f, double phi)
      : AzimuthFrame(f, std::cos(phi), std::sin(phi)) {}
  // The same from the direction (dx, dy) (any length > 0).
  AzimuthFrame(const data::HeightField& f, double dx, double dy) {
    x_major = std::abs(dx) >= std::abs(dy);
    const double major = x_major ? dx : dy, minor = x_major ? dy : dx;
    step = major >= 0 ? 1 : -1;
    slope = minor / major;
    const double snapped = std::round(slope);
    if (std::abs(slope - snapped) < 1e-6) slope = snapped;  // float azimuths are off by ~1e-7
    metres_per_step = static_cast<float>(f.cell_size * std::sqrt(1.0 + slope * slope));
    major_size = x_major ? f.width : f.height;
    minor_size = x_major ? f.height : f.width;
  }

  // Scaled terrain height at major coordinate u on the line b = offset + slope * u, or false
  // when that point is outside the field.
  bool height_at(const data::HeightField& f, float scale, double offset, int u, double& b,
                 float& h) const {
    b = offset + slope * u;
    if (b < 0 || b > minor_size - 1) return false;
    int bi = static_cast<int>(b);
    float t = static_cast<float>(b - bi);
    if (bi >= minor_size - 1) {
      bi = minor_size - 1;
      t = 0;
    }
    const float h0 = x_major ? f.at(u, bi) : f.at(bi, u);
    const float h1 = t > 0 ? (x_major ? f.at(u, bi + 1) : f.at(bi + 1, u)) : h0;
    h = scale * (h0 + t * (h1 - h0));
    return true;
  }
};

// Splits a sample offset (in cells) into floor and fraction, snapping fractions within 1e-5
// of a grid line onto it: the axis and diagonal directions, whose cos / sin are off by ~1e-8,
// then land exactly on samples (the pyramid march and the light-horizon march).
inline void split_offset(double v, int& whole, float& frac) {
  double f = std::floor(v), r = v - f;
  if (r > 1 - 1e-5) {
    f += 1;
    r = 0;
  } else if (r < 1e-5) {
    r = 0;
  }
  whole = static_cast<int>(f);
  frac = static_cast<float>(r);
}

// Azimuth k of n, rounded to float once, so that every sweep path and ray_horizon build the
// same frame.
inline float azimuth_angle(int k, int n) {
  return static_cast<float>(2.0 * 3.14159265358979323846 * k / n);
}

// Elevation slope from receiver (j_p, h_p) to occluder (j_q, h_q); j = step * u.
inline float slope_between(int j_p, float h_p, int j_q, float h_q, float metres_per_step) {
  return (h_q - h_p) / (static_cast<float>(j_q - j_p) * metres_per_step);
}

}  // namespace penumbra::terrain_shadow::detail
