// The room accuracy measurement shared by the placement accuracy tests
// (probe_placement_accuracy_test.cpp) and the probe_bake benchmark group's placement sweep
// (tests/bench/probe_bake_bench.cpp; docs/probe_bake.md, "Accuracy", "Error versus probe
// count"): the point sets, their reference irradiance (the reference integrator's direct + one
// bounce, the same light transport as the capture) and the relative RMS error of a cloud's
// interpolated irradiance over a set.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "common/random_draws.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_bake/bake_scene.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

namespace penumbra::probe_bake::accuracy {

// The six axis normals evaluated at every point.
inline const std::array<glm::vec3, 6> kNormals = {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                                  glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                                                  glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};

struct PointSet {
  std::vector<glm::vec3> points, ref;  // ref: 6 per point (kNormals)
};

// Reference irradiance (environment + lights + one bounce) at the set's points, 6 normals each:
// environment_irradiance (256 samples; 0 without a map), light_irradiance (256) and
// indirect_irradiance (1,024).
inline void reference_values(const reference::Scene& traced, PointSet& set) {
  std::vector<reference::Receiver> rec;
  for (const glm::vec3& p : set.points)
    for (const glm::vec3& n : kNormals) rec.push_back({p, n});
  reference::LightOptions lo;
  lo.samples = 256;
  reference::BounceOptions bo;
  bo.samples = 1024;
  reference::IrradianceOptions eo;
  eo.samples = 256;
  const auto env = reference::environment_irradiance(traced, rec, eo);  // 0 without a map
  const auto l = reference::light_irradiance(traced, rec, lo);
  const auto b = reference::indirect_irradiance(traced, rec, bo);
  for (std::size_t i = 0; i < rec.size(); ++i)
    set.ref.push_back(reference::combine(reference::combine(env[i], l[i]), b[i]).mean);
}

// Relative RMS error of the cloud's irradiance over a point set (6 normals, 3 channels):
// sqrt(sum (E_probe - E_ref)^2 / sum E_ref^2), the probes interpolated by ProbeTetWalk.
inline double set_error(const data::ProbeCloud& cloud, const PointSet& ps) {
  const probe_cloud::ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(cloud));
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ps.points.size(); ++i) {
    const probe_cloud::ProbeSh e = walk.interpolate(walk.locate(ps.points[i], -1));
    for (int k = 0; k < 6; ++k) {
      const auto y = sh::eval_basis<probe_cloud::kProbeShBands>(kNormals[k]);
      for (int c = 0; c < 3; ++c) {
        double v = 0;
        for (std::size_t j = 0; j < y.size(); ++j) v += e[c][j] * y[j];
        const double r = ps.ref[i * 6 + k][c];
        num += (v - r) * (v - r);
        den += r * r;
      }
    }
  }
  return std::sqrt(num / den);
}

// The room's three point sets (scenes/room.json; the same points as
// ProbeBakeAccuracy.RoomErrorVersusSpacing, one generator, seed 5):
//  [0] 120 random points in free space (0.1 m clear of every solid along the axes);
//  [1] 60 within one (1 m) spacing of the inner wall on its dark side (x in [0.25, 1],
//      y < 1.5: away from the lamp and the doorway), the leak metric's points;
//  [2] 60 mirrored on its lit side.
// Points only; reference_values() adds the reference.
enum RoomSet { kFree = 0, kDarkSide = 1, kLitSide = 2 };
inline std::array<PointSet, 3> room_point_sets(const BakeScene& s) {
  std::array<PointSet, 3> sets;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ux(-4.6f, 4.6f), uy(-3.6f, 3.6f), uz(0.3f, 3.7f);
  auto& free = sets[kFree].points;
  while (free.size() < 120) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, ux, uy, uz);
    bool clear = !s.inside(p);
    for (float d : {0.1f, -0.1f})
      for (int k = 0; k < 3; ++k) {
        glm::vec3 q = p;
        q[k] += d;
        clear = clear && !s.inside(q);
      }
    if (clear) free.push_back(p);
  }
  std::uniform_real_distribution<float> lx(0.25f, 1.0f), ly(-3.6f, 1.5f);
  while (sets[kDarkSide].points.size() < 60)
    sets[kDarkSide].points.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, lx, ly, uz));
  while (sets[kLitSide].points.size() < 60)
    sets[kLitSide].points.push_back(penumbra::test::draw_zyx<glm::vec3>(rng, lx, ly, uz) *
                                    glm::vec3(-1, 1, 1));
  return sets;
}

// The three sets with their reference values.
inline std::array<PointSet, 3> room_point_sets(const BakeScene& s, const reference::Scene& traced) {
  std::array<PointSet, 3> sets = room_point_sets(s);
  for (PointSet& set : sets) reference_values(traced, set);
  return sets;
}

}  // namespace penumbra::probe_bake::accuracy
