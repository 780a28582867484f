// The held-out check of ./penumbra tune (issue 17, docs/tune.md): tune on scenes/tune_ridge.json,
// then measure the chosen configuration of every system that met the budget there on the two
// scenes tune never saw (tune_valley, tune_hills: other terrain crops, objects and sky
// rotations); each error must stay within 1.5x the budget. At 3% the blockers cannot meet the
// budget on the tuning scene (their floor there is about 5.5%: docs/tune.md), so the check runs
// at 3% (terrain, probes) and at 6% (terrain, blockers, probes). The spherical lights meet
// neither (33% off the reference's one bounce at best, docs/tune.md): reported, not checked.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "tune/tune.h"

namespace penumbra::tune {
namespace {

const std::filesystem::path kRoot = PENUMBRA_SOURCE_DIR;
const std::filesystem::path kData = PENUMBRA_SHARED_DATA;

TuneScene scene(const char* name) {
  return load_tune_scene(kRoot / "scenes" / (std::string(name) + ".json"), kData);
}

void print(const char* what, const settings::TuneResult& r) {
  std::printf("  %-10s error %6.2f%%  met %d  evaluated %d of %d\n", what, 100 * r.error, r.met,
              r.evaluations, r.grid);
}

void check_held_out(double budget, int systems_expected_to_meet) {
  const TuneOptions options;
  const TuneScene ridge = scene("tune_ridge");
  const settings::TunedSettings s = run_tune(ridge, budget, options);
  std::printf("budget %.2f%%, tuned on %s:\n", 100 * budget, ridge.name.c_str());
  print("terrain", s.terrain.result);
  print("blockers", s.blockers.result);
  print("sph.lights", s.spherical_lights.result);
  print("probes", s.probes.result);
  const int met = s.terrain.result.met + s.blockers.result.met + s.spherical_lights.result.met +
                  s.probes.result.met;
  EXPECT_GE(met, systems_expected_to_meet);
  for (const settings::TuneResult* r :
       {&s.terrain.result, &s.blockers.result, &s.spherical_lights.result, &s.probes.result}) {
    EXPECT_TRUE(r->tuned);
    EXPECT_LT(r->evaluations, r->grid);  // not an exhaustive search
    EXPECT_EQ(r->met, r->error <= budget);
  }
  for (const char* name : {"tune_valley", "tune_hills"}) {
    const TuneScene held = scene(name);
    const settings::TunedSettings h = evaluate_settings(held, s, options);
    std::printf("held out %s:\n", name);
    print("terrain", h.terrain.result);
    print("blockers", h.blockers.result);
    print("sph.lights", h.spherical_lights.result);
    print("probes", h.probes.result);
    if (s.terrain.result.met) {
      EXPECT_LE(h.terrain.result.error, 1.5 * budget) << name;
    }
    if (s.blockers.result.met) {
      EXPECT_LE(h.blockers.result.error, 1.5 * budget) << name;
    }
    if (s.spherical_lights.result.met) {
      EXPECT_LE(h.spherical_lights.result.error, 1.5 * budget) << name;
    }
    if (s.probes.result.met) {
      EXPECT_LE(h.probes.result.error, 1.5 * budget) << name;
    }
  }
}

TEST(TuneHeldOut, Budget3PercentTerrainAndProbes) {
  check_held_out(0.03, 2);
}

TEST(TuneHeldOut, Budget6PercentAllSystems) {
  check_held_out(0.06, 3);
}

}  // namespace
}  // namespace penumbra::tune
