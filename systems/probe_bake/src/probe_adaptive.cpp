// Adaptive placement (probe_adaptive.h): spawn and merge ([Sukys14] sec. 3.1.1) and gradient
// ascent (sec. 3.1.2) with the k-means reduction of black probes (sec. 3.1.3).
#include "penumbra/systems/probe_bake/probe_adaptive.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>

#include "penumbra/systems/probe_bake/probe_placement.h"
#include "penumbra/systems/probe_bake/probe_sampling.h"
#include "penumbra/systems/probe_cloud/delaunay_tetrahedralization.h"

namespace penumbra::probe_bake {
namespace {

// Unique Delaunay edges (a < b), sorted. Points must be pairwise distinct.
std::vector<std::pair<std::int32_t, std::int32_t>> delaunay_edges(
    std::span<const glm::vec3> points) {
  std::vector<glm::dvec3> d(points.begin(), points.end());
  const auto dt = probe_cloud::delaunay_tetrahedralize(d);
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (std::size_t c = 0; c < dt.finite_count; ++c) {
    const auto& v = dt.vertices[c];
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edges.emplace_back(std::min(v[i], v[j]), std::max(v[i], v[j]));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

std::size_t stride_of(int bands) {
  return static_cast<std::size_t>(3 * bands * bands);
}

}  // namespace

std::vector<glm::vec3> spawn_merge_points(const BakeScene& scene, const ProbeVolume& volume,
                                          int bands, float invalid_share,
                                          const SpawnMergeSettings& s, const CaptureFn& capture,
                                          AdaptiveReport* report) {
  AdaptiveReport rep;
  const std::size_t stride = stride_of(bands);
  std::vector<glm::vec3> pos = grid_points(volume);
  rep.initial = pos.size();
  std::vector<float> sh, share;
  capture(pos, false, sh, share);
  rep.captured += pos.size();
  std::vector<DirectionSamples> samples(pos.size());
  double mean = 0;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    samples[i] = sample_irradiance(std::span(sh).subspan(i * stride, stride), bands);
    for (float v : samples[i]) mean += v;
  }
  // The contrast floor: dark_floor of the initial grid's mean luminance (over all directions).
  const float floor = static_cast<float>(
      s.dark_floor * mean / std::max<double>(1, double(pos.size()) * kSampleDirections));
  std::vector<bool> spawned(pos.size(), false);
  const float spacing = volume.spacing;
  rep.stop = AdaptiveReport::Stop::kIterations;
  for (int it = 0; it < s.max_iterations; ++it) {
    const auto edges = delaunay_edges(pos);
    auto valid = [&](std::int32_t i) { return !(share[i] > invalid_share); };
    std::vector<std::tuple<float, std::int32_t, std::int32_t>> merges, spawns;
    for (const auto& [a, b] : edges) {
      if (!valid(a) || !valid(b)) continue;
      const float len = glm::length(pos[b] - pos[a]);
      const float c = probe_contrast(samples[a], samples[b], floor);
      if (c < s.merge_contrast && len <= s.merge_length * spacing && !spawned[a] && !spawned[b])
        merges.emplace_back(c, a, b);
      else if (c > s.spawn_contrast && len >= s.spawn_length * spacing)
        spawns.emplace_back(-c, a, b);
    }
    std::sort(merges.begin(), merges.end());
    std::sort(spawns.begin(), spawns.end());
    std::vector<bool> gone(pos.size(), false);
    std::vector<glm::vec3> added;
    std::vector<bool> added_spawned;
    for (const auto& [c, a, b] : merges) {
      if (gone[a] || gone[b]) continue;
      const glm::vec3 m = 0.5f * (pos[a] + pos[b]);
      if (scene.inside(m)) continue;
      gone[a] = gone[b] = true;
      added.push_back(m);
      added_spawned.push_back(false);
      ++rep.merged;
    }
    const std::size_t after_merge = pos.size() - 2 * added.size() + added.size();
    bool capped = false;
    std::size_t spawned_now = 0;
    for (const auto& [c, a, b] : spawns) {
      if (after_merge + spawned_now >= s.max_probes) {
        capped = true;
        break;
      }
      const glm::vec3 m = 0.5f * (pos[a] + pos[b]);
      if (scene.inside(m)) continue;
      added.push_back(m);
      added_spawned.push_back(true);
      ++spawned_now;
    }
    rep.spawned += spawned_now;
    rep.iterations = it + 1;
    if (added.empty()) {
      rep.stop = AdaptiveReport::Stop::kNoChange;
      rep.counts.push_back(pos.size());
      break;
    }
    // Keep the survivors in order, then the new probes; capture only the new ones.
    std::vector<glm::vec3> npos;
    std::vector<float> nsh, nshare;
    std::vector<DirectionSamples> nsamples;
    std::vector<bool> nspawned;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (gone[i]) continue;
      npos.push_back(pos[i]);
      nsh.insert(nsh.end(), sh.begin() + static_cast<std::ptrdiff_t>(i * stride),
                 sh.begin() + static_cast<std::ptrdiff_t>((i + 1) * stride));
      nshare.push_back(share[i]);
      nsamples.push_back(samples[i]);
      nspawned.push_back(spawned[i]);
    }
    std::vector<float> ash, ashare;
    capture(added, false, ash, ashare);
    rep.captured += added.size();
    for (std::size_t k = 0; k < added.size(); ++k) {
      // A midpoint can coincide with a survivor (two merges / spawns meeting): keep one.
      if (std::find(npos.begin(), npos.end(), added[k]) != npos.end()) continue;
      npos.push_back(added[k]);
      nsh.insert(nsh.end(), ash.begin() + static_cast<std::ptrdiff_t>(k * stride),
                 ash.begin() + static_cast<std::ptrdiff_t>((k + 1) * stride));
      nshare.push_back(ashare[k]);
      nsamples.push_back(sample_irradiance(std::span(ash).subspan(k * stride, stride), bands));
      nspawned.push_back(added_spawned[k]);
    }
    pos = std::move(npos);
    sh = std::move(nsh);
    share = std::move(nshare);
    samples = std::move(nsamples);
    spawned = std::move(nspawned);
    rep.counts.push_back(pos.size());
    if (capped || pos.size() >= s.max_probes) {
      rep.stop = AdaptiveReport::Stop::kProbeCap;
      break;
    }
  }
  if (report) *report = std::move(rep);
  return pos;
}

std::vector<glm::vec3> gradient_points(const BakeScene& scene, const ProbeVolume& volume, int bands,
                                       float invalid_share, const GradientSettings& s,
                                       const CaptureFn& capture, AdaptiveReport* report) {
  AdaptiveReport rep;
  const std::size_t stride = stride_of(bands);
  std::vector<glm::vec3> pos = grid_points(volume);
  const std::size_t n = pos.size();
  rep.initial = n;
  std::vector<float> sh, share;
  capture(pos, true, sh, share);  // light decoupling: indirect only
  rep.captured += n;
  const float spacing = volume.spacing;
  std::vector<DirectionSamples> samples(n);
  std::vector<bool> black(n), inside(n);
  for (std::size_t i = 0; i < n; ++i) {
    samples[i] = sample_irradiance(std::span(sh).subspan(i * stride, stride), bands);
    inside[i] = share[i] > invalid_share;
    black[i] = !inside[i] && *std::max_element(samples[i].begin(), samples[i].end()) <= 0;
  }
  std::vector<float> step(n, s.step);
  const glm::vec3 lo = volume.min, hi = volume.max;
  rep.stop = AdaptiveReport::Stop::kIterations;
  for (int it = 0; it < s.max_iterations; ++it) {
    std::vector<std::size_t> who;
    std::vector<glm::vec3> to;
    float largest = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (inside[i] || black[i]) continue;
      const glm::vec3 g = irradiance_vector(samples[i]);
      const float len = step[i] * spacing * glm::length(g);
      if (len < s.min_step * spacing) continue;
      largest = std::max(largest, len);
      who.push_back(i);
      // Stay in the probe volume (the ascent is towards surfaces and lights).
      to.push_back(glm::clamp(pos[i] + step[i] * spacing * g, lo, hi));
    }
    rep.iterations = it + 1;
    if (who.empty()) {
      rep.stop = AdaptiveReport::Stop::kSmallStep;
      break;
    }
    std::vector<float> nsh, nshare;
    capture(to, true, nsh, nshare);
    rep.captured += to.size();
    for (std::size_t k = 0; k < who.size(); ++k) {
      const std::size_t i = who[k];
      const DirectionSamples ns =
          sample_irradiance(std::span(nsh).subspan(k * stride, stride), bands);
      // Second order ascent: landed in the dark (behind geometry) or inside a solid: revert
      // and shrink the step.
      if (nshare[k] > invalid_share || *std::max_element(ns.begin(), ns.end()) <= 0 ||
          scene.inside(to[k])) {
        step[i] *= 0.5f;
        ++rep.reverted;
        continue;
      }
      pos[i] = to[k];
      samples[i] = ns;
      ++rep.moves;
    }
    rep.counts.push_back(n);
  }
  // K-means of the black probes (sec. 3.1.3): k = ceil(count x black_fraction) clusters,
  // seeded by every (count / k)-th black probe in grid order, Lloyd iterations; each cluster is
  // kept as its member nearest the centroid.
  std::vector<glm::vec3> out;
  std::vector<glm::vec3> dark;
  for (std::size_t i = 0; i < n; ++i) (black[i] ? dark : out).push_back(pos[i]);
  rep.black = dark.size();
  if (!dark.empty()) {
    const std::size_t k = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::ceil(double(dark.size()) * s.black_fraction)));
    std::vector<glm::vec3> centre(k);
    for (std::size_t j = 0; j < k; ++j) centre[j] = dark[j * dark.size() / k];
    std::vector<std::size_t> label(dark.size(), 0);
    for (int it = 0; it < s.kmeans_iterations; ++it) {
      bool changed = false;
      for (std::size_t p = 0; p < dark.size(); ++p) {
        std::size_t best = 0;
        float bd = std::numeric_limits<float>::infinity();
        for (std::size_t j = 0; j < k; ++j) {
          const float d2 = glm::dot(dark[p] - centre[j], dark[p] - centre[j]);
          if (d2 < bd) {
            bd = d2;
            best = j;
          }
        }
        changed = changed || label[p] != best;
        label[p] = best;
      }
      std::vector<glm::dvec3> sum(k, glm::dvec3(0.0));
      std::vector<std::size_t> count(k, 0);
      for (std::size_t p = 0; p < dark.size(); ++p) {
        sum[label[p]] += glm::dvec3(dark[p]);
        ++count[label[p]];
      }
      for (std::size_t j = 0; j < k; ++j)
        if (count[j]) centre[j] = glm::vec3(sum[j] / double(count[j]));
      if (!changed && it > 0) break;
    }
    for (std::size_t j = 0; j < k; ++j) {
      std::size_t best = dark.size();
      float bd = std::numeric_limits<float>::infinity();
      for (std::size_t p = 0; p < dark.size(); ++p) {
        if (label[p] != j) continue;
        const float d2 = glm::dot(dark[p] - centre[j], dark[p] - centre[j]);
        if (d2 < bd) {
          bd = d2;
          best = p;
        }
      }
      if (best < dark.size()) {
        out.push_back(dark[best]);
        ++rep.clusters;
      }
    }
  }
  // Probes that met (two ascents to one maximum) are one probe.
  std::vector<glm::vec3> unique;
  for (const glm::vec3& q : out) {
    bool dup = false;
    for (const glm::vec3& u : unique)
      if (glm::dot(q - u, q - u) < 1e-6f * spacing * spacing) {
        dup = true;
        break;
      }
    if (!dup) unique.push_back(q);
  }
  if (report) *report = std::move(rep);
  return unique;
}

}  // namespace penumbra::probe_bake
