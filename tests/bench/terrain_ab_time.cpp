// terrain_ab_time: one stage of the terrain system timed on one thread and on two, for comparing
// two builds of it (scripts/terrain_ab.py builds each variant's copy of this program and runs
// them in interleaved rounds). The stages run as the bench group "terrain" runs them, on its
// 256 x 256 scene (terrain_bench_reference.h):
//
//   horizons   sweep_horizons, 32 azimuths, the workspace reused ("horizons alone, sweep")
//   env        TerrainShadowing<4>::update: horizons, normals and transfer ("env update")
//   light      add_spherical_light, one light 6 m above the centre (the bench's first light)
//   edit       apply_brush + update_edit, crater and raise in turn at the centre: 20 edits after
//              a full update, timed as their mean ("local edit 16x16")
//
// Usage: terrain_ab_time CASE [REPS]
// Prints one JSON line: the case, REPS, the median and minimum milliseconds of REPS calls on a
// one-thread and on a two-thread arena, and the FNV-1a hash of the stage's output (horizon
// angles, transfer, irradiance; for `edit` the horizons and transfer after the 20 edits), which
// says whether two builds compute the same floats.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tbb/task_arena.h>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "terrain_bench_reference.h"

namespace {

using namespace penumbra;
namespace tbr = penumbra::bench::terrain;
namespace ts = penumbra::terrain_shadow;

constexpr int kSize = 256;

struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
};

struct Timing {
  double median, min;
};

// `reps` calls of `call` inside `arena`, each timed by the milliseconds it returns.
Timing time_calls(tbb::task_arena& arena, int reps, const std::function<double()>& call) {
  std::vector<double> t;
  arena.execute([&] {
    for (int i = 0; i < reps; ++i) t.push_back(call());
  });
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One stage: a call that returns its milliseconds, and the hash of what the last call produced.
struct Stage {
  std::function<double()> call;
  std::function<std::uint64_t()> hash;
};

Stage horizons_stage(std::shared_ptr<const data::HeightField> field) {
  struct State {
    std::shared_ptr<const data::HeightField> field;
    ts::HorizonParams params;
    ts::HorizonGrid grid;
    ts::SweepWorkspace workspace;
  };
  auto s = std::make_shared<State>();
  s->field = std::move(field);
  s->params.azimuths = 32;
  s->params.height_scale = tbr::kHeightScale;
  s->params.clamp_at_zero = true;
  return {[s] {
            const auto t0 = std::chrono::steady_clock::now();
            ts::sweep_horizons(*s->field, s->params, ts::TexelRect::all(*s->field), s->grid,
                               s->workspace);
            return ms_since(t0);
          },
          [s] {
            Hash h;
            h.add(s->grid.angles.data(), s->grid.angles.size() * sizeof(float));
            return h.h;
          }};
}

Stage shadowing_stage(const std::string& name, std::shared_ptr<const data::HeightField> field) {
  struct State {
    std::shared_ptr<const data::HeightField> field;
    ts::TerrainShadowing<4> shadowing{ts::TerrainShadowConfig{}};
    std::vector<glm::vec3> irradiance;
    glm::vec3 light_centre{0.0f};
    ts::Brush brush;
  };
  auto s = std::make_shared<State>();
  s->field = std::move(field);
  const data::HeightField& f = *s->field;
  s->shadowing.update(s->field, tbr::kHeightScale);  // allocations
  const auto transfer_hash = [s] {
    Hash h;
    h.add(s->shadowing.transfer().data(),
          s->shadowing.transfer().size() * sizeof(s->shadowing.transfer()[0]));
    return h.h;
  };
  if (name == "env")
    return {[s] {
              const auto t0 = std::chrono::steady_clock::now();
              s->shadowing.update(s->field, tbr::kHeightScale);
              return ms_since(t0);
            },
            transfer_hash};
  if (name == "light") {
    const int x = (f.width - 1) / 2, y = (f.height - 1) / 2;
    s->light_centre = {x * f.cell_size, y * f.cell_size, tbr::kHeightScale * f.at(x, y) + 6.0f};
    s->irradiance.resize(static_cast<std::size_t>(f.width) * f.height);
    return {[s] {
              std::fill(s->irradiance.begin(), s->irradiance.end(), glm::vec3(0.0f));
              const auto t0 = std::chrono::steady_clock::now();
              s->shadowing.add_spherical_light(s->light_centre, 2.0f, {400.0f, 380.0f, 340.0f},
                                               s->irradiance);
              return ms_since(t0);
            },
            [s] {
              Hash h;
              h.add(s->irradiance.data(), s->irradiance.size() * sizeof(glm::vec3));
              return h.h;
            }};
  }
  // edit: the bench's held brush (edit_bench.cpp), 20 edits after a full update, their mean.
  s->brush.radius = 8.0f * f.cell_size;
  s->brush.centre = glm::vec2(0.5f * (f.width - 1), 0.5f * (f.height - 1)) * f.cell_size +
                    glm::vec2(0.5f * f.cell_size);
  s->brush.strength = 2.0f;
  return {[s] {
            constexpr int kEdits = 20;
            s->shadowing.update(s->field, tbr::kHeightScale);
            std::shared_ptr<const data::HeightField> edited = s->field;
            double total = 0;
            for (int n = 0; n < kEdits; ++n) {
              s->brush.kind = n % 2 == 0 ? ts::BrushKind::kCrater : ts::BrushKind::kRaise;
              const auto t0 = std::chrono::steady_clock::now();
              ts::EditResult e = ts::apply_brush(edited, s->brush);
              s->shadowing.update_edit(e.field, tbr::kHeightScale, e.changed);
              total += ms_since(t0);
              edited = e.field;
            }
            return total / kEdits;
          },
          [s, transfer_hash] {
            Hash h;
            const auto& angles = s->shadowing.horizons().angles;
            h.add(angles.data(), angles.size() * sizeof(float));
            h.h ^= transfer_hash();
            return h.h;
          }};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string name = argc > 1 ? argv[1] : "";
  const int reps = argc > 2 ? std::atoi(argv[2]) : 15;
  if ((name != "horizons" && name != "env" && name != "light" && name != "edit") || reps < 1 ||
      argc > 3) {
    std::fprintf(stderr,
                 "usage: terrain_ab_time horizons|env|light|edit [REPS >= 1]\n"
                 "  got case '%s', REPS %d\n",
                 name.c_str(), reps);
    return 2;
  }
  auto field = tbr::load_scene(tbr::kSceneName, kSize);
  const Stage stage = name == "horizons" ? horizons_stage(field) : shadowing_stage(name, field);
  tbb::task_arena one(1), two(2);
  stage.call();  // warm-up: buffers, caches, the branch predictor's first guesses
  const Timing t1 = time_calls(one, reps, stage.call);
  const Timing t2 = time_calls(two, reps, stage.call);
  std::printf(
      "{\"case\": \"%s\", \"reps\": %d, \"one_thread_ms\": %.4f, \"two_threads_ms\": %.4f, "
      "\"one_thread_min_ms\": %.4f, \"two_threads_min_ms\": %.4f, \"hash\": \"%016llx\"}\n",
      name.c_str(), reps, t1.median, t2.median, t1.min, t2.min,
      static_cast<unsigned long long>(stage.hash()));
  return 0;
}
