// Sampling building blocks of the reference integrator (header-only): a seeded random stream,
// stratified points in [0,1)^2, direction warps with their densities, and the paired-strata
// mean / standard-error accumulator every estimator reports through.
//
// Error bars (paired strata, Cochran, "Sampling Techniques", 3rd ed., sec. 5A.12): the unit
// square is cut into H strata and each stratum gets TWO independent uniform points. With
// estimates a_h, b_h from stratum h, the estimate is (1/2H) sum (a_h + b_h) and the unbiased
// estimate of its variance is (1/H^2) sum (a_h - b_h)^2 / 4. So the reported standard error
// keeps the variance reduction of stratification yet stays an honest (unbiased) error bar.
//
// Everything here is a pure function or a value type: thread-safe to use from any thread,
// one Pcg32 per thread of work.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>

#include <glm/ext/vector_double2.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace penumbra::reference {

// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mix.
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// PCG32, XSH-RR 64/32 (O'Neill 2014, pcg-random.org). Constructed from (seed, stream, salt):
// each receiver index gets its own reproducible stream whatever thread runs it, and each
// estimator its own salt, so two estimators with one seed do not share random numbers.
class Pcg32 {
 public:
  Pcg32(std::uint64_t seed, std::uint64_t stream, std::uint64_t salt = 0) {
    const std::uint64_t key = splitmix64(seed ^ splitmix64(salt));
    inc_ = (splitmix64(key ^ splitmix64(stream + 0x632BE59BD9B4E019ull)) << 1) | 1u;
    state_ = 0;
    next_u32();
    state_ += splitmix64(key + stream);
    next_u32();
  }
  std::uint32_t next_u32() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  // Uniform in [0, 1) with 24 random bits (never returns 1).
  float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
  // Uniform in [0, 1) with 53 random bits (never returns 1).
  double next_double() {
    const std::uint64_t hi = next_u32() >> 5, lo = next_u32() >> 6;
    return static_cast<double>((hi << 26) | lo) * 0x1p-53;
  }

 private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_ = 1;
};

// H = nx * ny strata over [0,1)^2: the exact factorisation of the requested count with the
// most square shape (aspect at most 4:1), else the largest square-ish grid below it (count()
// says which). With stratified = false every "stratum" is the whole square (independent uniform
// points; the pairing then only affects the bookkeeping).
struct StrataGrid {
  int nx = 1;
  int ny = 1;
  bool stratified = true;

  static StrataGrid for_count(int strata, bool stratified) {
    strata = strata < 1 ? 1 : strata;
    int root = static_cast<int>(std::sqrt(static_cast<double>(strata)));
    while ((root + 1) * (root + 1) <= strata) ++root;  // guard against sqrt rounding
    while (root * root > strata) --root;
    for (int nx = root; nx >= 1; --nx) {
      if (strata % nx == 0 && strata / nx <= 4 * nx) return {nx, strata / nx, stratified};
    }
    return {root, strata / root, stratified};
  }
  int count() const { return nx * ny; }
  // A uniform point in stratum h (0 <= h < count()), 53 random bits per coordinate (the
  // environment sampler inverts CDFs whose small steps need more than a float's 24 bits).
  glm::dvec2 point(int h, Pcg32& rng) const {
    const double a = rng.next_double(), b = rng.next_double();
    if (!stratified) return {a, b};
    // (i + a) / n can round up to exactly 1: keep the half-open interval.
    constexpr double kBelowOne = 0x1.fffffffffffffp-1;
    return {std::fmin((h % nx + a) / nx, kBelowOne), std::fmin((h / nx + b) / ny, kBelowOne)};
  }
};

// A [0,1)^2 point rounded to float without reaching 1.
inline glm::vec2 to_float(glm::dvec2 u) {
  return {std::fmin(static_cast<float>(u.x), 0x1.fffffep-1f),
          std::fmin(static_cast<float>(u.y), 0x1.fffffep-1f)};
}

// Accumulates K-channel estimates in pairs (two from each stratum), in double.
template <std::size_t K>
class PairedMean {
 public:
  void add_pair(const std::array<double, K>& a, const std::array<double, K>& b) {
    for (std::size_t k = 0; k < K; ++k) {
      sum_[k] += a[k] + b[k];
      const double d = a[k] - b[k];
      diff2_[k] += d * d;
      differing_[k] += d != 0;
    }
    ++pairs_;
  }
  std::size_t pairs() const { return pairs_; }
  double mean(std::size_t k) const { return pairs_ ? sum_[k] / (2.0 * pairs_) : 0.0; }
  // Standard error of mean(k): sqrt((1/H^2) sum (a-b)^2 / 4), H = pairs().
  double std_error(std::size_t k) const {
    return pairs_ ? std::sqrt(diff2_[k]) / (2.0 * static_cast<double>(pairs_)) : 0.0;
  }
  // Pairs whose two estimates of channel k differ: the degrees of freedom of its variance
  // estimate. Few (under ~30) means the error bar is itself uncertain (Student-t tails).
  std::size_t differing_pairs(std::size_t k) const { return differing_[k]; }
  // The smallest differing_pairs() over the channels with a nonzero error (0 if none).
  std::size_t dof() const {
    std::size_t m = 0;
    for (std::size_t k = 0; k < K; ++k) {
      if (differing_[k] > 0 && (m == 0 || differing_[k] < m)) m = differing_[k];
    }
    return m;
  }

 private:
  std::array<double, K> sum_{};
  std::array<double, K> diff2_{};
  std::array<std::size_t, K> differing_{};
  std::size_t pairs_ = 0;
};

// Orthonormal frame around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited", JCGT 6(1)).
struct Frame {
  glm::vec3 t, b, n;
  explicit Frame(const glm::vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
  }
  glm::vec3 to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// --- Warps from [0,1)^2 to directions (local frame, z = axis), area-preserving up to the
// density given with each, so strata stay compact (PBRT 3rd ed. sec. 13.6).

// Shirley-Chiu concentric map of the square onto the unit disk.
inline glm::vec2 concentric_disk(glm::vec2 u) {
  const float a = 2 * u.x - 1, b = 2 * u.y - 1;
  if (a == 0 && b == 0) return {0, 0};
  constexpr float kQuarterPi = std::numbers::pi_v<float> / 4;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2 * kQuarterPi - kQuarterPi * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// Cosine-weighted hemisphere (Malley's method); density cos(theta) / pi.
inline glm::vec3 cosine_hemisphere(glm::vec2 u) {
  const glm::vec2 d = concentric_disk(u);
  const float z2 = 1 - d.x * d.x - d.y * d.y;
  return {d.x, d.y, std::sqrt(z2 > 0 ? z2 : 0.0f)};
}

// Uniform on the sphere (Archimedes: z uniform); density 1 / (4 pi).
inline glm::vec3 uniform_sphere(glm::vec2 u) {
  const float z = 1 - 2 * u.x;
  const float r = std::sqrt(std::fmax(0.0f, 4 * u.x * (1 - u.x)));  // sqrt(1 - z^2)
  const float phi = 2 * std::numbers::pi_v<float> * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Uniform on the hemisphere z > 0; density 1 / (2 pi).
inline glm::vec3 uniform_hemisphere(glm::vec2 u) {
  const float z = 1 - u.x;
  const float r = std::sqrt(std::fmax(0.0f, u.x * (2 - u.x)));
  const float phi = 2 * std::numbers::pi_v<float> * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Uniform in the cone of half-angle theta_max around z, given one_minus_cos = 1 - cos(theta_max)
// (pass it computed without cancellation for small cones); density 1 / (2 pi one_minus_cos).
inline glm::vec3 uniform_cone(glm::vec2 u, double one_minus_cos) {
  const double t = u.x * one_minus_cos;  // 1 - cos(theta)
  const double sin_theta = std::sqrt(std::fmax(0.0, t * (2 - t)));
  const double phi = 2 * std::numbers::pi * u.y;
  return {static_cast<float>(sin_theta * std::cos(phi)),
          static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(1 - t)};
}

}  // namespace penumbra::reference
