#include "penumbra/systems/probe_cloud/probe_systems.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <utility>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "penumbra/components/frame_time.h"
#include "penumbra/components/probe_anchor.h"
#include "penumbra/components/probe_lighting.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/finite.h"

namespace penumbra::probe_cloud {
namespace {

using components::FrameTime;
using components::ProbeAnchor;
using components::ProbeCloudResource;
using components::ProbeLighting;
using components::Transform;

using LightingSh = sh::CoeffsRgb<ProbeLighting::kBands>;
constexpr std::size_t kMaxNamedEntities = 20;  // entities named per frame in the report
constexpr std::size_t kPrefetchRows = 32;      // walk_chunk hints the rows' lines this far ahead

std::string entity_name(ecs::Entity e) {
  return "entity " + std::to_string(e.index) + "v" + std::to_string(e.generation);
}

using data::finite;

bool same(const ProbeWalkSettings& a, const ProbeWalkSettings& b) {
  return a.max_steps == b.max_steps && a.far_cells == b.far_cells;
}

void prepare(jobs::SystemContext& ctx) {
  ecs::World& w = ctx.world();
  ProbeWalkState& state = w.resource<ProbeWalkState>();
  const ProbeCloudResource* res = w.try_resource<const ProbeCloudResource>();
  const ProbeSettingsResource* settings = w.try_resource<const ProbeSettingsResource>();
  const ProbeWalkSettings walk_settings = settings ? settings->walk : ProbeWalkSettings{};
  const std::shared_ptr<const data::ProbeCloud> cloud = res ? res->cloud : nullptr;
  const std::uint64_t generation = res ? res->generation : 0;
  if (cloud == state.source && generation == state.source_generation &&
      same(walk_settings, state.settings) && (state.walk || !state.error.empty() || !cloud))
    return;
  state.source = cloud;
  state.source_generation = generation;
  state.settings = walk_settings;
  state.walk.reset();
  state.error.clear();
  ++state.generation;
  if (!cloud) return;
  try {
    state.walk = std::make_shared<const ProbeTetWalk>(cloud, walk_settings);
  } catch (const std::exception& e) {
    state.error = e.what();
  }
}

// irradiance += (sample - irradiance) * alpha: this frame's interpolation blended straight in.
void smooth_towards(ProbeLighting& l, const LightingSh& sample, float alpha) {
  for (std::size_t ch = 0; ch < 3; ++ch)
    for (std::size_t k = 0; k < sample[ch].size(); ++k)
      l.irradiance[ch][k] += (sample[ch][k] - l.irradiance[ch][k]) * alpha;
}

// This frame's interpolation for r into l: as it is for the first sample (never smoothed up
// from black) or without smoothing, else blended in.
void publish(const ProbeTetWalk& walk, const ProbeWalkResult& r, ProbeLighting& l, float alpha) {
  if (!l.valid || alpha >= 1.0f) {
    walk.interpolate(r, l.irradiance);
  } else {
    LightingSh sample;
    walk.interpolate(r, sample);
    smooth_towards(l, sample, alpha);
  }
  l.valid = true;
}

// Per-chunk partial report, merged in chunk order by finish.
struct Partial {
  std::size_t entities = 0, unchanged = 0, fallbacks = 0, steps = 0;
  int max_steps = 0;
  std::size_t rejected = 0;
  std::vector<std::string> errors;  // the first kMaxNamedEntities of this chunk
};

void walk_chunk(jobs::SystemContext& ctx,
                const ecs::ChunkView<const Transform, ProbeAnchor, ProbeLighting>& c,
                Partial& out) {
  const ecs::World& w = ctx.world();
  const ProbeWalkState& state = w.resource<const ProbeWalkState>();
  if (!state.walk) return;
  const ProbeTetWalk& walk = *state.walk;
  const ProbeSettingsResource* settings = w.try_resource<const ProbeSettingsResource>();
  const FrameTime* time = w.try_resource<const FrameTime>();
  const float dt = time ? time->dt : (settings ? settings->default_dt : 1.0f / 60.0f);
  const bool smooth = settings && settings->smoothing == ProbeSmoothing::kExponential;
  const float alpha = smooth ? smoothing_alpha(dt, settings->time_constant) : 1.0f;
  const auto transforms = c.get<const Transform>();
  const auto anchors = c.get<ProbeAnchor>();
  const auto lighting = c.get<ProbeLighting>();
  const auto entities = c.entities();
  const std::uint64_t generation = state.generation;
  const auto cached_cell = [&](std::size_t k) {
    return anchors[k].generation == generation ? anchors[k].cell : kNoCell;
  };
  const auto lines = [](const void* p, std::size_t bytes, int write) {
    const char* b = static_cast<const char*>(p);
    for (std::size_t o = 0; o < bytes; o += 64)
      write ? __builtin_prefetch(b + o, 1) : __builtin_prefetch(b + o);
    write ? __builtin_prefetch(b + bytes - 1, 1) : __builtin_prefetch(b + bytes - 1);
  };
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (i + kPrefetchRows < c.size()) {  // the rows themselves, further ahead than the cells
      lines(&transforms[i + kPrefetchRows], sizeof(Transform), 0);
      lines(&anchors[i + kPrefetchRows], sizeof(ProbeAnchor), 1);
      lines(&lighting[i + kPrefetchRows], sizeof(ProbeLighting), 1);
    }
    if (i + kPrefetchCells < c.size()) walk.prefetch(cached_cell(i + kPrefetchCells), false);
    if (i + kPrefetchProbes < c.size()) walk.prefetch(cached_cell(i + kPrefetchProbes), true);
    ProbeAnchor& a = anchors[i];
    const glm::vec3 p = glm::vec3(transforms[i].world * glm::vec4(a.offset, 1.0f));
    if (!finite(p)) {
      if (out.rejected++ >= kMaxNamedEntities) continue;
      out.errors.push_back(entity_name(entities[i]) +
                           ": probe sample point is not finite (transform or anchor offset); "
                           "skipped, its lighting kept");
      continue;
    }
    ProbeLighting& l = lighting[i];
    const bool cached = a.generation == generation;
    if (cached && l.valid && a.point == p) {
      // Not moved since its last walk, same cloud: the same sample; only the smoothing moves,
      // towards that sample rebuilt from the cached cell (ProbeTetWalk::at: no walk).
      ++out.unchanged;
      if (alpha < 1.0f) publish(walk, walk.at(a.cell, p), l, alpha);
      continue;
    }
    const ProbeWalkResult r = walk.locate(p, cached ? a.cell : kNoCell);
    a.cell = r.cell;
    a.generation = generation;
    a.point = p;
    a.steps = r.steps;
    a.fallback = r.fallback;
    publish(walk, r, l, alpha);
    ++out.entities;
    out.fallbacks += r.fallback ? 1 : 0;
    out.steps += static_cast<std::size_t>(r.steps);
    out.max_steps = std::max(out.max_steps, r.steps);
  }
}

}  // namespace

float smoothing_alpha(float dt, float time_constant) {
  if (!(time_constant > 0) || !std::isfinite(dt)) return 1.0f;
  return 1.0f - std::exp(-std::max(dt, 0.0f) / time_constant);
}

void emplace_probe_cloud_resources(ecs::World& world,
                                   std::shared_ptr<const data::ProbeCloud> cloud) {
  if (!world.try_resource<ProbeCloudResource>()) {
    ProbeCloudResource& r = world.emplace_resource<ProbeCloudResource>();
    if (cloud) r.replace(std::move(cloud));
  }
  if (!world.try_resource<ProbeSettingsResource>()) world.emplace_resource<ProbeSettingsResource>();
  if (!world.try_resource<ProbeWalkState>()) world.emplace_resource<ProbeWalkState>();
  if (!world.try_resource<ProbeWalkReport>()) world.emplace_resource<ProbeWalkReport>();
}

void add_probe_cloud_systems(jobs::Schedule& schedule) {
  schedule.add_task("probes.prepare", prepare)
      .reads<ProbeCloudResource, ProbeSettingsResource>()
      .writes<ProbeWalkState>();

  auto partials = std::make_shared<std::vector<Partial>>();
  jobs::SystemBuilder b = schedule.add_chunks<const Transform, ProbeAnchor, ProbeLighting>(
      "probes.walk",
      [partials](jobs::SystemContext& ctx,
                 const ecs::ChunkView<const Transform, ProbeAnchor, ProbeLighting>& c) {
        walk_chunk(ctx, c, (*partials)[c.ordinal()]);
      });
  b.reads<ProbeWalkState, ProbeSettingsResource, FrameTime>().writes<ProbeWalkReport>();
  jobs::System& s = b.system();
  auto inner_prepare = std::move(s.prepare);
  s.prepare = [inner_prepare, partials](ecs::World& w, const ecs::TypeSet& ex, std::size_t& n) {
    const std::size_t chunks = inner_prepare(w, ex, n);
    partials->assign(chunks, Partial{});
    return chunks;
  };
  s.finish = [partials](jobs::SystemContext& ctx) {
    ProbeWalkReport& report = ctx.world().resource<ProbeWalkReport>();
    report = {};
    for (Partial& p : *partials) {  // chunk order: independent of the thread count
      report.entities += p.entities;
      report.unchanged += p.unchanged;
      report.fallbacks += p.fallbacks;
      report.steps += p.steps;
      report.max_steps = std::max(report.max_steps, p.max_steps);
      report.rejected += p.rejected;
      for (std::string& e : p.errors)
        if (report.errors.size() < kMaxNamedEntities) report.errors.push_back(std::move(e));
    }
    ctx.report_work(report.entities, report.unchanged);  // walked; not moved, same cloud
    if (report.rejected > report.errors.size())
      report.errors.push_back("... and " + std::to_string(report.rejected - report.errors.size()) +
                              " more entities with a non-finite sample point");
  };
}

}  // namespace penumbra::probe_cloud
