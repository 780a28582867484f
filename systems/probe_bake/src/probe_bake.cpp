// The probe bake (probe_bake.h): grid placement, radiance_sh capture with back faces from the
// scene's solids, virtual offset, dilation, Delaunay build ([Sukys14] sec. 3.1, 3.2).
#include "penumbra/systems/probe_bake/probe_bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "penumbra/reference/radiance_sh.h"
#include "penumbra/sh/convolution.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

namespace penumbra::probe_bake {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Capture {
  std::vector<float> sh;  // irradiance, 3 b^2 per point (cloud layout)
  std::vector<float> share, dc_err, dc;
  std::vector<glm::vec3> escape_dir;
  std::vector<float> escape_distance;
  std::uint64_t rays = 0;
};

template <int N>
void capture(const reference::Scene& traced, const BakeScene& scene,
             std::span<const glm::vec3> points, const reference::RadianceShOptions& base,
             std::uint64_t first_index, Capture& out, std::size_t chunk, std::size_t& done,
             std::size_t total, const BakeProgress& progress) {
  constexpr int kC = N * N;
  const std::size_t n = points.size();
  out.sh.assign(n * 3 * kC, 0.0f);
  out.share.assign(n, 0.0f);
  out.dc_err.assign(n, 0.0f);
  out.dc.assign(n, 0.0f);
  out.escape_dir.assign(n, glm::vec3(0.0f));
  out.escape_distance.assign(n, 0.0f);
  reference::RadianceShOptions o = base;
  o.back_face = [&scene](const glm::vec3& origin, const glm::vec3& dir, const reference::Hit& h) {
    // The point just before the hit, on the ray's side: inside a solid -> the ray leaves it.
    const float back = std::min(0.5f * h.distance, 1e-3f);
    return scene.inside(origin + (h.distance - back) * dir);
  };
  // Irradiance DC = pi * radiance DC (band 0 weight of irradiance_convolve).
  const float kPi = 3.14159265358979f;
  for (std::size_t start = 0; start < n; start += chunk) {
    const std::size_t count = std::min(chunk, n - start);
    o.first_index = first_index + start;
    const auto est = reference::radiance_sh<N>(traced, points.subspan(start, count), o);
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = start + k;
      const auto& e = est[k];
      for (int c = 0; c < 3; ++c) {
        const sh::Coeffs<N> irr = sh::irradiance_convolve<N>(e.mean[c]);
        std::copy(irr.begin(), irr.end(),
                  out.sh.begin() + static_cast<std::ptrdiff_t>((i * 3 + c) * kC));
        out.dc_err[i] = std::max(out.dc_err[i], kPi * e.std_error[c][0]);
        out.dc[i] += irr[0] / 3;
      }
      out.share[i] = e.back_face_share();
      out.escape_dir[i] = e.escape_dir;
      out.escape_distance[i] = e.escape_distance;
      out.rays += e.rays;
    }
    done += count;
    if (progress) progress(done, total);
  }
}

void capture_any(int bands, const reference::Scene& traced, const BakeScene& scene,
                 std::span<const glm::vec3> points, const reference::RadianceShOptions& o,
                 std::uint64_t first_index, Capture& out, std::size_t chunk, std::size_t& done,
                 std::size_t total, const BakeProgress& progress) {
  switch (bands) {
    case 2:
      return capture<2>(traced, scene, points, o, first_index, out, chunk, done, total, progress);
    case 3:
      return capture<3>(traced, scene, points, o, first_index, out, chunk, done, total, progress);
    default:
      return capture<4>(traced, scene, points, o, first_index, out, chunk, done, total, progress);
  }
}

}  // namespace

data::ProbeCloud bake_probe_cloud(const BakeScene& scene, const BakeSettings& settings,
                                  BakeReport* report, const BakeProgress& progress) {
  const reference::Scene traced(scene.desc);
  return bake_probe_cloud(scene, traced, settings, report, progress);
}

data::ProbeCloud bake_probe_cloud(const BakeScene& scene, const reference::Scene& traced,
                                  const BakeSettings& s, BakeReport* report,
                                  const BakeProgress& progress) {
  const auto t0 = Clock::now();
  if (s.bands < data::kProbeMinBands || s.bands > data::kProbeMaxBands)
    throw std::invalid_argument("bake_probe_cloud: bands = " + std::to_string(s.bands) +
                                " must be in 2..4");
  if (s.samples < 2) throw std::invalid_argument("bake_probe_cloud: samples must be >= 2");
  if (!(s.spacing >= 0) || !std::isfinite(s.spacing))
    throw std::invalid_argument("bake_probe_cloud: spacing must be finite and >= 0");
  ProbeVolume volume = scene.volume;
  if (s.spacing > 0) volume.spacing = s.spacing;
  const float spacing = volume.spacing;

  reference::RadianceShOptions o;
  o.samples = s.samples;
  o.bounce_samples = s.bounce_samples;
  o.bounce = s.bounce;
  o.seed = s.seed;
  const std::size_t chunk = std::max<std::size_t>(1, s.chunk);
  const std::size_t stride = static_cast<std::size_t>(3 * s.bands * s.bands);
  BakeReport rep;

  // Adaptive placement's captures: streams from 2^40 on (the bake's own start at 0), numbered
  // in call order. Indirect only (light decoupling, [Sukys14] sec. 3.1.2): the bounce alone
  // (RadianceShOptions::direct off).
  std::uint64_t placement_stream = std::uint64_t{1} << 40;
  const CaptureFn placement_capture = [&](std::span<const glm::vec3> pts, bool indirect,
                                          std::vector<float>& sh_out,
                                          std::vector<float>& share_out) {
    std::size_t d = 0;
    Capture c;
    reference::RadianceShOptions oc = o;
    oc.direct = !indirect;
    capture_any(s.bands, traced, scene, pts, oc, placement_stream, c, chunk, d, pts.size(), {});
    placement_stream += pts.size();
    rep.placement_rays += c.rays;
    sh_out = std::move(c.sh);
    share_out = std::move(c.share);
  };
  std::vector<glm::vec3> placed;
  switch (s.placement) {
    case PlacementMethod::kGrid:
      placed = grid_points(volume);
      break;
    case PlacementMethod::kSpawnMerge:
      placed = spawn_merge_points(scene, volume, s.bands, s.validity_settings.invalid_share,
                                  s.spawn_merge, placement_capture, &rep.adaptive);
      break;
    case PlacementMethod::kGradient:
      placed = gradient_points(scene, volume, s.bands, s.validity_settings.invalid_share,
                               s.gradient, placement_capture, &rep.adaptive);
      break;
  }
  rep.placement_seconds = seconds_since(t0);
  const std::size_t n = placed.size();
  rep.placed = n;
  rep.probes.resize(n);
  std::size_t done = 0, total = n;
  Capture first;
  capture_any(s.bands, traced, scene, placed, o, 0, first, chunk, done, total, progress);
  rep.capture_seconds = seconds_since(t0) - rep.placement_seconds;
  rep.rays += first.rays;

  std::vector<glm::vec3> positions = placed;
  std::vector<float> sh = first.sh;
  std::vector<ProbeState> state(n, ProbeState::kValid);
  std::uint64_t next_stream = n;  // capture streams: one per captured point, never reused
  for (std::size_t i = 0; i < n; ++i) {
    rep.probes[i].placed = placed[i];
    rep.probes[i].back_face_share = first.share[i];
    rep.probes[i].dc_std_error = first.dc_err[i];
    rep.probes[i].dc = first.dc[i];
  }
  // Moved and added probes stay in the placed probes' bounding box: a probe poking out of a
  // flat hull face (a grid's) turns that face into long sliver triangles across the volume,
  // whose outer cells extrapolate one side of a wall onto the other (in the room at 0.5 m a
  // probe pushed out of the ball to z = 0.35 under the z = 0.5 layer lit the inner wall's dark
  // side through the floor's hull: dark-side error 18x; docs/probe_bake.md "Edge rays").
  glm::vec3 box_min = n ? placed[0] : glm::vec3(0.0f), box_max = box_min;
  for (const glm::vec3& q : placed) {
    box_min = glm::min(box_min, q);
    box_max = glm::max(box_max, q);
  }
  auto in_box = [&](const glm::vec3& q) { return glm::clamp(q, box_min, box_max); };
  const auto t1 = Clock::now();
  if (s.validity) {
    const ValiditySettings& v = s.validity_settings;
    std::vector<std::size_t> moved;
    std::vector<glm::vec3> moved_to;
    for (std::size_t i = 0; i < n; ++i) {
      if (!(first.share[i] > v.invalid_share)) continue;
      state[i] = ProbeState::kBlack;  // invalid until offset or dilated
      const float reach = v.max_offset * spacing;
      if (first.escape_distance[i] <= reach) {
        const glm::vec3 d = first.escape_dir[i];
        // The exit face's outward normal (the hit's normal faces the ray, i.e. inwards): the
        // probe leaves perpendicular to that face, so a grid row through a wall lands as a row
        // on each face, not scattered by the sampled escape direction (a probe just off a flat
        // hull face or row turns it into slivers that leak across the wall).
        auto exit_point = [&](const glm::vec3& dir, float fallback) {
          const reference::Hit h = traced.first_hit(placed[i], dir, reach);
          if (!h) return placed[i] + dir * (fallback + v.clearance * spacing);
          const glm::vec3 out = -h.normal;
          const float perp = h.distance * std::max(0.0f, glm::dot(dir, out));
          return placed[i] + out * (perp + v.clearance * spacing);
        };
        moved.push_back(i);
        moved_to.push_back(in_box(exit_point(d, first.escape_distance[i])));
        if (v.both_sides) {
          // The opposite side: the exit along -d (a thin wall's other face).
          const reference::Hit h = traced.first_hit(placed[i], -d, reach);
          if (h) {
            moved.push_back(i);
            moved_to.push_back(in_box(exit_point(-d, h.distance)));
          }
        }
      }
    }
    if (!moved.empty()) {
      total += moved.size();
      if (progress) progress(done, total);
      Capture second;
      // Streams n + k: independent of the first pass, fixed for the same inputs.
      capture_any(s.bands, traced, scene, moved_to, o, n, second, chunk, done, total, progress);
      next_stream += moved.size();
      rep.rays += second.rays;
      for (std::size_t k = 0; k < moved.size(); ++k) {
        if (second.share[k] > v.invalid_share) continue;
        std::size_t i = moved[k];
        if (state[i] == ProbeState::kOffset) {  // its other side: a probe of its own
          i = positions.size();
          positions.push_back(moved_to[k]);
          state.push_back(ProbeState::kOffset);
          sh.resize(sh.size() + stride);
          rep.probes.emplace_back();
          rep.probes.back().placed = placed[moved[k]];
          ++rep.split;
        }
        state[i] = ProbeState::kOffset;
        positions[i] = moved_to[k];
        std::copy_n(second.sh.begin() + static_cast<std::ptrdiff_t>(k * stride), stride,
                    sh.begin() + static_cast<std::ptrdiff_t>(i * stride));
        rep.probes[i].back_face_share = second.share[k];
        rep.probes[i].dc_std_error = second.dc_err[k];
        rep.probes[i].dc = second.dc[k];
      }
    }
    rep.black =
        dilate(positions, state, sh, stride, v.dilation_radius * spacing, v.dilation_passes);
  }
  rep.validity_seconds = seconds_since(t1);
  const auto te = Clock::now();
  for (int round = 1; s.edge_rays.enabled && round <= s.edge_rays.max_iterations; ++round) {
    std::vector<glm::vec3> pts = edge_ray_points(scene, traced, positions, s.edge_rays, &rep.edge);
    std::erase_if(pts, [&](const glm::vec3& q) { return in_box(q) != q; });
    if (pts.empty()) break;
    rep.edge_rounds = round;
    total += pts.size();
    Capture extra;
    capture_any(s.bands, traced, scene, pts, o, next_stream, extra, chunk, done, total, progress);
    next_stream += pts.size();
    rep.rays += extra.rays;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (s.validity && extra.share[k] > s.validity_settings.invalid_share) {
        ++rep.edge_dropped;
        continue;
      }
      ++rep.edge_added;
      positions.push_back(pts[k]);
      state.push_back(ProbeState::kValid);
      sh.insert(sh.end(), extra.sh.begin() + static_cast<std::ptrdiff_t>(k * stride),
                extra.sh.begin() + static_cast<std::ptrdiff_t>((k + 1) * stride));
      ProbeRecord& r = rep.probes.emplace_back();
      r.placed = pts[k];
      r.back_face_share = extra.share[k];
      r.dc_std_error = extra.dc_err[k];
      r.dc = extra.dc[k];
      r.edge_round = round;
    }
  }
  rep.edge_seconds = seconds_since(te);
  double rel_sum = 0;
  std::size_t rel_count = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    ProbeRecord& r = rep.probes[i];
    r.position = positions[i];
    r.state = state[i];
    switch (state[i]) {
      case ProbeState::kValid:
        rep.valid += rep.probes[i].edge_round == 0;
        break;
      case ProbeState::kOffset:
        rep.offset += i < n;
        break;
      case ProbeState::kDilated:
        ++rep.dilated;
        break;
      case ProbeState::kBlack:
        break;
    }
    if ((state[i] == ProbeState::kValid || state[i] == ProbeState::kOffset) && r.dc > 0) {
      const double rel = r.dc_std_error / r.dc;
      rel_sum += rel;
      ++rel_count;
      rep.max_rel_std_error = std::max(rep.max_rel_std_error, rel);
    }
  }
  rep.mean_rel_std_error = rel_count ? rel_sum / static_cast<double>(rel_count) : 0.0;

  const auto t2 = Clock::now();
  probe_cloud::ProbeCloudBuildSettings build;
  build.bands = s.bands;
  probe_cloud::ProbeCloudBuildReport br;
  data::ProbeCloud cloud = probe_cloud::build_probe_cloud(positions, sh, build, &br);
  rep.merged = br.merged_duplicates;
  rep.snapped = br.snapped_coordinates;
  const auto validation = probe_cloud::validate_probe_cloud(cloud);
  rep.valid_cloud = validation.ok();
  rep.validation_errors = validation.errors;
  rep.build_seconds = seconds_since(t2);
  rep.total_seconds = seconds_since(t0);
  if (report) *report = std::move(rep);
  return cloud;
}

}  // namespace penumbra::probe_bake
