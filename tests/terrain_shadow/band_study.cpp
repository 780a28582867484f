// terrain_band_study: why the environment error of the terrain shadow system is not monotonic
// in the SH band count (issue 20; docs/terrain_shadow.md, "SH bands: the experiment").
//
// For every accuracy scene (terrain_reference.h) under sky.exr and sunset.exr (rotated 0.7 rad,
// as accuracy_test.cpp), at the 32 x 32 stride-8 receivers, it prints the relative RMS error
// against the Monte Carlo reference of several shadings of the SAME horizons (the system's sweep,
// n_phi 32), band counts 3 to kMaxBands:
//   method      the system as built (TerrainShadowing<N>, defaults: sweep, n_phi 32, the exact
//               transfer, TransferMethod::kExact);
//   table_old   the previous transfer, proj_N(V_N x C_N) ([Meier13] eq. 4.21 as a truncated triple
//               product) from the same wedge tables: the "before" of the fix;
//   quadV_old   the same truncated product with V_N by dense quadrature instead of the wedge
//               tables (isolates the tables and their z rotations);
//   V6xC6       V and C at 6 bands, product at 6, then truncated to N (couplings up to band 5);
//   exact       L_N . proj_N(V max(0, n.w)) by dense quadrature: the exact transfer, whose only
//               error left is the radiance's truncation L_N (the environment's own ringing) and
//               the horizons;
//   linear      L_N . proj_N(V (n.w)): the cosine unclamped (what the new transfer would give
//               without raising the horizon to the tangent plane);
//   exact_L12   L_12 . proj_12(V max(0, n.w)): the truncation all but gone; what is left is the
//               horizon model (sweep, linear interpolation across wedges) and reference noise;
//   key_exact   the map's brightest source as a key light (issue 15: detect_light_sources, its
//               texels blackened in the SH, TerrainShadowing::add_key_light) plus the rest of the
//               map by the exact transfer at N bands: whether the zigzag is the sun's.
// Run: build/<dir>/tests/terrain_shadow/terrain_band_study [scene ...]. Not a test: about 10 s per
// scene in a release build.
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/environment/light_source_detection.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "penumbra/systems/terrain_shadow/transfer.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"
#include "sh_any.h"  // systems/terrain_shadow/src: the library's internal any-band basis
#include "terrain_reference.h"

namespace penumbra::terrain_reference {
namespace {

namespace ts = terrain_shadow;
constexpr int kL = 12;  // bands of the dense projections
constexpr int kC = kL * kL;
constexpr int kMaxBands = 8;
constexpr float kRotation = 0.7f;
constexpr double kPi = std::numbers::pi;

// Real SH of the library's convention at kL bands (sh_any.h, the exact transfer's own).
void eval_sh(double x, double y, double z, double* out) {
  terrain_shadow::detail::eval_basis_any(kL, x, y, z, out);
}

using Dense = std::array<double, kC>;
using DenseRgb = std::array<Dense, 3>;

// The map's projection at kL bands, turned by `rotation` about z (the reference's and
// sh::rotate_z's convention: a lobe at u ends up at R u).
DenseRgb project_map(const data::EnvironmentMap& map, float rotation) {
  DenseRgb out{};
  std::vector<DenseRgb> rows(static_cast<std::size_t>(map.height));
  tbb::parallel_for(0, map.height, [&](int y) {
    DenseRgb acc{};
    const double w = sh::equirect_texel_solid_angle(y, map.width, map.height);
    std::array<double, kC> b;
    for (int x = 0; x < map.width; ++x) {
      const glm::vec3 u = sh::equirect_direction((x + 0.5f) / map.width, (y + 0.5f) / map.height);
      const double c = std::cos(rotation), s = std::sin(rotation);
      eval_sh(c * u.x - s * u.y, s * u.x + c * u.y, u.z, b.data());
      const float* t = map.texel(x, y);
      for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < kC; ++i) acc[ch][i] += w * t[ch] * b[i];
    }
    rows[static_cast<std::size_t>(y)] = acc;
  });
  for (const DenseRgb& r : rows)
    for (int ch = 0; ch < 3; ++ch)
      for (int i = 0; i < kC; ++i) out[ch][i] += r[ch][i];
  return out;
}

struct Projections {
  Dense v{}, vc{}, vlin{};  // V, V max(0, n.w), V (n.w)
};

// Dense quadrature over the method's visibility model ([Meier13] eq. 4.15-4.18: horizon linear
// across each wedge, clamped at 0), split at the tangent plane so each piece is smooth.
Projections project_texel(const float* angles, int n_phi, const glm::vec3& n) {
  static const sh::SphereQuadrature ga = sh::SphereQuadrature::gauss(16, 1);
  static const sh::SphereQuadrature ge = sh::SphereQuadrature::gauss(24, 1);
  Projections p;
  const double dphi = 2 * kPi / n_phi;
  std::array<double, kC> b;
  for (int k = 0; k < n_phi; ++k) {
    const double h0 = angles[k], h1 = angles[(k + 1) % n_phi];
    for (std::size_t a = 0; a < ga.directions.size(); ++a) {
      const double f = 0.5 * (ga.directions[a].z + 1);
      const double phi = (k + f) * dphi, wa = 0.5 * dphi * ga.weights[a] / (2 * kPi);
      const double h = std::max(0.0, h0 + f * (h1 - h0));
      const double cp = std::cos(phi), sp = std::sin(phi);
      const double t = std::atan2(-(n.x * cp + n.y * sp), n.z);  // n.w = 0
      const double split = std::clamp(t, h, kPi / 2);
      for (int piece = 0; piece < 2; ++piece) {
        const double e0 = piece == 0 ? h : split, e1 = piece == 0 ? split : kPi / 2;
        if (e1 <= e0) continue;
        for (std::size_t e = 0; e < ge.directions.size(); ++e) {
          const double el = e0 + 0.5 * (e1 - e0) * (ge.directions[e].z + 1);
          const double we = wa * 0.5 * (e1 - e0) * ge.weights[e] / (2 * kPi) * std::cos(el);
          const double x = cp * std::cos(el), y = sp * std::cos(el), z = std::sin(el);
          const double cosine = n.x * x + n.y * y + n.z * z;
          eval_sh(x, y, z, b.data());
          for (int i = 0; i < kC; ++i) {
            p.v[i] += we * b[i];
            p.vlin[i] += we * cosine * b[i];
            if (piece == 1) p.vc[i] += we * std::max(cosine, 0.0) * b[i];
          }
        }
      }
    }
  }
  return p;
}

template <int N>
sh::Coeffs<N> to_coeffs(const Dense& d) {
  sh::Coeffs<N> c;
  for (int i = 0; i < N * N; ++i) c[i] = static_cast<float>(d[i]);
  return c;
}
template <int N>
sh::CoeffsRgb<N> to_rgb(const DenseRgb& d) {
  return {to_coeffs<N>(d[0]), to_coeffs<N>(d[1]), to_coeffs<N>(d[2])};
}
// Band weights ("window") of the shading sum_l w_l L_l . T_l; 0: none.
enum class Window { kNone, kLanczos, kHann, kHalfLast };
double window_weight(Window w, int l, int n) {
  switch (w) {
    case Window::kNone:
      return 1;
    case Window::kLanczos: {
      const double x = kPi * l / n;
      return l == 0 ? 1 : std::sin(x) / x;
    }
    case Window::kHann:
      return 0.5 * (1 + std::cos(kPi * l / (n + 1)));
    case Window::kHalfLast:
      return l == n - 1 ? 0.5 : 1;
  }
  return 1;
}
glm::vec3 dense_dot(const DenseRgb& l, const Dense& t, int n, Window w = Window::kNone) {
  glm::dvec3 e(0.0);
  for (int b = 0; b < n; ++b) {
    const double wb = window_weight(w, b, n);
    for (int i = b * b; i < (b + 1) * (b + 1); ++i)
      e += wb * glm::dvec3(l[0][i], l[1][i], l[2][i]) * t[i];
  }
  return glm::vec3(e);
}
template <int N>
glm::vec3 dot_rgb(const sh::CoeffsRgb<N>& l, const sh::Coeffs<N>& t) {
  return {sh::dot<N>(l[0], t), sh::dot<N>(l[1], t), sh::dot<N>(l[2], t)};
}

// The previous transfer, proj_N(V_N x C_N), by the library's truncated product.
template <int N>
sh::Coeffs<N> old_transfer(const sh::Coeffs<N>& v, const glm::vec3& n) {
  return sh::product<N>(v, sh::rotate_zh<N>(sh::zh_clamped_cosine<N>(), n));
}

struct Table {
  std::vector<std::string> rows;
  std::vector<std::array<double, kMaxBands + 1>> err;
  int row(const std::string& name) {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i] == name) return static_cast<int>(i);
    rows.push_back(name);
    err.push_back({});
    err.back().fill(-1);
    return static_cast<int>(rows.size()) - 1;
  }
};

template <int N>
void method_bands(const std::shared_ptr<const data::HeightField>& field, const ReceiverSet& rs,
                  const DenseRgb& l, const std::vector<Projections>& proj,
                  const ts::HorizonGrid& hz, const std::vector<glm::vec3>& normals,
                  const ReferenceIrradiance& ref, Table& table) {
  const data::HeightField& f = *field;
  ts::TerrainShadowing<N> system;  // defaults: sweep, n_phi 32, the exact transfer
  system.update(field, 1.0f);
  const std::size_t cells = static_cast<std::size_t>(f.width) * f.height;
  const sh::CoeffsRgb<N> ln = to_rgb<N>(l);
  const sh::CoeffsRgb<6> l6 = to_rgb<6>(l);
  const ts::WedgeTable<N> wedges(32, ts::WedgeDomain::kHemisphere, 64);
  std::vector<glm::vec3> table_old(cells), quad_old(cells), v6(cells), method(cells);
  for (std::size_t r = 0; r < rs.texels.size(); ++r) {
    const std::size_t i = rs.texels[r];
    const int x = static_cast<int>(i % f.width), y = static_cast<int>(i / f.width);
    const glm::vec3 n = normals[i];
    const sh::Coeffs<N> vt = wedges.visibility(hz.texel(x, y));
    table_old[i] = dot_rgb<N>(ln, old_transfer<N>(vt, n));
    method[i] = dot_rgb<N>(ln, system.transfer()[i]);
    quad_old[i] = dot_rgb<N>(ln, old_transfer<N>(to_coeffs<N>(proj[r].v), n));
    const sh::Coeffs<6> t6 = old_transfer<6>(to_coeffs<6>(proj[r].v), n);
    glm::vec3 e(0.0f);
    for (int j = 0; j < N * N; ++j) e += glm::vec3(l6[0][j], l6[1][j], l6[2][j]) * t6[j];
    v6[i] = e;
  }
  table.err[table.row("method")][N] = compare(method, ref.texels, ref.environment).rel_rms;
  table.err[table.row("table_old")][N] = compare(table_old, ref.texels, ref.environment).rel_rms;
  table.err[table.row("quadV_old")][N] = compare(quad_old, ref.texels, ref.environment).rel_rms;
  table.err[table.row("V6xC6")][N] = compare(v6, ref.texels, ref.environment).rel_rms;
}

void study(std::string_view scene, std::string_view map_name, float rotation, int samples) {
  const auto field = load_terrain(scene, 256);
  const data::EnvironmentMap map = load_hdri(map_name);
  const ReceiverSet rs = texel_receivers(*field, 1.0f, 8);
  Lighting lighting;
  lighting.environment = &map;
  lighting.rotation_z = rotation;
  ReferenceOptions o;
  o.samples = samples;
  const ReferenceIrradiance ref = reference_irradiance(*field, 1.0f, rs, lighting, o);
  const DenseRgb l = project_map(map, rotation);
  ts::TerrainShadowing<4> ts4;  // default horizons: sweep, n_phi 32
  ts4.update(field, 1.0f);
  std::vector<Projections> proj(rs.texels.size());
  tbb::parallel_for(std::size_t{0}, rs.texels.size(), [&](std::size_t r) {
    const std::size_t i = rs.texels[r];
    const int x = static_cast<int>(i % field->width), y = static_cast<int>(i / field->width);
    proj[r] = project_texel(ts4.horizons().texel(x, y), 32, ts4.normals()[i]);
  });
  Table table;
  method_bands<3>(field, rs, l, proj, ts4.horizons(), ts4.normals(), ref, table);
  method_bands<4>(field, rs, l, proj, ts4.horizons(), ts4.normals(), ref, table);
  method_bands<5>(field, rs, l, proj, ts4.horizons(), ts4.normals(), ref, table);
  method_bands<6>(field, rs, l, proj, ts4.horizons(), ts4.normals(), ref, table);
  const std::size_t cells = field->heights.size();
  for (int n = 3; n <= kMaxBands; ++n) {
    std::vector<glm::vec3> exact(cells), linear(cells), lanczos(cells), hann(cells), half(cells);
    for (std::size_t r = 0; r < rs.texels.size(); ++r) {
      exact[rs.texels[r]] = dense_dot(l, proj[r].vc, n);
      linear[rs.texels[r]] = dense_dot(l, proj[r].vlin, n);
      lanczos[rs.texels[r]] = dense_dot(l, proj[r].vc, n, Window::kLanczos);
      hann[rs.texels[r]] = dense_dot(l, proj[r].vc, n, Window::kHann);
      half[rs.texels[r]] = dense_dot(l, proj[r].vc, n, Window::kHalfLast);
    }
    table.err[table.row("exact")][n] = compare(exact, ref.texels, ref.environment).rel_rms;
    table.err[table.row("linear")][n] = compare(linear, ref.texels, ref.environment).rel_rms;
    table.err[table.row("ex_lanczos")][n] = compare(lanczos, ref.texels, ref.environment).rel_rms;
    table.err[table.row("ex_hann")][n] = compare(hann, ref.texels, ref.environment).rel_rms;
    table.err[table.row("ex_half")][n] = compare(half, ref.texels, ref.environment).rel_rms;
  }
  std::vector<glm::vec3> full(cells);
  for (std::size_t r = 0; r < rs.texels.size(); ++r)
    full[rs.texels[r]] = dense_dot(l, proj[r].vc, kL);
  // The brightest source as a key light, the rest of the map in SH (as the system's
  // EnvironmentSources::kKeyLights does at 4 bands).
  {
    environment::DetectionSettings ds;
    ds.source_count = 1;
    const environment::LightSourceDetection det = environment::detect_light_sources(map, ds);
    if (!det.sources.empty()) {
      const environment::DetectedSource& src = det.sources[0];
      data::EnvironmentMap rest = map;
      for (std::uint32_t t : src.texels)
        for (int ch = 0; ch < 3; ++ch) rest.rgb[3 * static_cast<std::size_t>(t) + ch] = 0;
      const DenseRgb lr = project_map(rest, rotation);
      const float cr = std::cos(rotation), sr = std::sin(rotation);
      const glm::vec3 d =
          glm::normalize(glm::vec3(cr * src.direction.x - sr * src.direction.y,
                                   sr * src.direction.x + cr * src.direction.y, src.direction.z));
      std::vector<float> horizons;
      ts4.key_light_horizons(d, horizons);
      std::vector<glm::vec3> key(cells, glm::vec3(0.0f));
      ts4.add_key_light(d, src.angular_radius, src.irradiance, horizons, key);
      for (int n = 3; n <= kMaxBands; ++n) {
        std::vector<glm::vec3> e(cells);
        for (std::size_t r = 0; r < rs.texels.size(); ++r)
          e[rs.texels[r]] = dense_dot(lr, proj[r].vc, n) + key[rs.texels[r]];
        table.err[table.row("key_exact")][n] = compare(e, ref.texels, ref.environment).rel_rms;
      }
      std::printf("  (key light: %.1f deg up, radius %.2f deg, %.0f%% of the energy)\n",
                  src.elevation_deg, src.angular_radius * 180 / kPi, 100 * src.energy_share);
    }
  }
  // The truncation alone: exact_N against exact_L12 (no horizon error, no reference noise).
  const std::vector<reference::RgbEstimate> converged = [&] {
    std::vector<reference::RgbEstimate> c(rs.texels.size());
    for (std::size_t r = 0; r < rs.texels.size(); ++r) c[r].mean = full[rs.texels[r]];
    return c;
  }();
  for (int n = 3; n <= kMaxBands; ++n) {
    std::vector<glm::vec3> exact(cells);
    for (std::size_t r = 0; r < rs.texels.size(); ++r)
      exact[rs.texels[r]] = dense_dot(l, proj[r].vc, n);
    table.err[table.row("ex_vs_L12")][n] = compare(exact, rs.texels, converged).rel_rms;
  }
  const ErrorSummary f = compare(full, ref.texels, ref.environment);
  std::printf("\n%s / %s (rotation %.1f, %d samples; ref se %.2f%%; exact_L%d %.2f%%)\n",
              std::string(scene).c_str(), std::string(map_name).c_str(), rotation, samples,
              100 * f.ref_rel_se, kL, 100 * f.rel_rms);
  std::printf("  %-10s", "bands");
  for (int n = 3; n <= kMaxBands; ++n) std::printf(" %7d", n);
  std::printf("\n");
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    std::printf("  %-10s", table.rows[r].c_str());
    for (int n = 3; n <= kMaxBands; ++n)
      table.err[r][n] < 0 ? std::printf(" %7s", "-")
                          : std::printf(" %6.2f%%", 100 * table.err[r][n]);
    std::printf("\n");
  }
  std::fflush(stdout);
}

// The dense basis must be the library's (up to float precision) for the comparison to mean
// anything; the map projection likewise.
void self_check() {
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 d = glm::normalize(
        glm::vec3(std::sin(k * 1.3f), std::cos(k * 0.7f), std::sin(k * 2.1f + 0.3f)));
    std::array<double, kC> b;
    eval_sh(d.x, d.y, d.z, b.data());
    const sh::Coeffs<6> y = sh::eval_basis<6>(d);
    for (int i = 0; i < 36; ++i) worst = std::max(worst, std::fabs(b[i] - y[i]));
  }
  const data::EnvironmentMap map = load_hdri("sunset");
  const DenseRgb l = project_map(map, kRotation);
  const sh::CoeffsRgb<5> l5 = environment_sh<5>(map, kRotation);
  double worst_l = 0, scale = 0;
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < 25; ++i) {
      worst_l = std::max(worst_l, std::fabs(l[ch][i] - l5[ch][i]));
      scale = std::max(scale, std::fabs(static_cast<double>(l5[ch][i])));
    }
  std::printf("self check: basis max diff %.2e, map projection max diff %.2e of %.3g\n", worst,
              worst_l, scale);
}

}  // namespace
}  // namespace penumbra::terrain_reference

int main(int argc, char** argv) {
  using namespace penumbra::terrain_reference;
  self_check();
  std::vector<std::string_view> scenes;
  for (int i = 1; i < argc; ++i) scenes.push_back(argv[i]);
  if (scenes.empty()) scenes.assign(kTerrainNames.begin(), kTerrainNames.end());
  for (std::string_view s : scenes)
    for (std::string_view m : {"sky", "sunset"}) study(s, m, kRotation, 1024);
  // The benchmark's own setting: mountains, sunset unrotated, 2048 directions.
  if (argc == 1) study("mountains", "sunset", 0.0f, 2048);
  return 0;
}
