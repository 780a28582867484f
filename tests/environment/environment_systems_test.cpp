// environment.sources (environment_systems.h): finds the sources of a new map once, leaves them
// until the map changes, and turns a rejected map into no sources and a message.
#include "penumbra/systems/environment/environment_systems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "common/frame_work.h"
#include "common/stability.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/sh/projection.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace t = penumbra::test;
using penumbra::components::EnvironmentLight;

namespace {

struct Fixture {
  penumbra::ecs::World world;
  penumbra::jobs::Schedule schedule;
  penumbra::jobs::Executor executor{2};
  Fixture() {
    env::DetectionSettings d;
    d.source_count = 1;
    env::emplace_environment_resources(world, d);
    env::add_environment_systems(schedule);
  }
  void set_map(const penumbra::data::EnvironmentMap& m) {
    EnvironmentLight& l = world.resource<EnvironmentLight>();
    l.map = std::make_shared<penumbra::data::EnvironmentMap>(m);
    ++l.version;
  }
};

TEST(EnvironmentSystems, FindsTheSourcesOfANewMapOnce) {
  Fixture f;
  f.world.emplace_resource<EnvironmentLight>();
  auto m = t::flat_map(256, 128, glm::vec3(0.3f));
  t::add_disc(m, t::dir_deg(40, 30), 3.0f, glm::vec3(3000));
  f.set_map(m);
  f.executor.run(f.schedule, f.world);
  const EnvironmentLight& l = f.world.resource<EnvironmentLight>();
  ASSERT_EQ(l.sources.size(), 1u);
  EXPECT_EQ(l.sources_version, l.version);
  EXPECT_LT(t::angle_deg(l.sources[0].direction, t::dir_deg(40, 30)), 1.0f);
  f.executor.run(f.schedule, f.world);  // unchanged map: no second detection
  EXPECT_EQ(f.world.resource<env::EnvironmentSettings>().detections, 1u);
  f.set_map(t::flat_map(256, 128, glm::vec3(0.3f)));  // no bright region
  f.executor.run(f.schedule, f.world);
  EXPECT_TRUE(f.world.resource<EnvironmentLight>().sources.empty());
  EXPECT_EQ(f.world.resource<env::EnvironmentSettings>().detections, 2u);
}

// The frame table's work report (jobs::report_work): one map, detected when new, skipped while
// unchanged; no report without an EnvironmentLight.
TEST(EnvironmentSystems, ReportsTheWorkItSkipsPerFrame) {
  Fixture f;
  f.executor.run(f.schedule, f.world);
  EXPECT_FALSE(t::system_timing(f.executor.last_frame(), "environment.sources").reported);
  f.world.emplace_resource<EnvironmentLight>();
  auto m = t::flat_map(128, 64, glm::vec3(0.3f));
  t::add_disc(m, t::dir_deg(40, 30), 3.0f, glm::vec3(3000));
  f.set_map(m);
  f.executor.run(f.schedule, f.world);
  const auto& s = t::system_timing(f.executor.last_frame(), "environment.sources");
  EXPECT_TRUE(s.reported);
  EXPECT_EQ(s.done, 1u);
  EXPECT_EQ(s.skipped, 0u);
  f.executor.run(f.schedule, f.world);
  const auto& still = t::system_timing(f.executor.last_frame(), "environment.sources");
  EXPECT_EQ(still.done, 0u) << "unchanged map";
  EXPECT_EQ(still.skipped, 1u);
}

TEST(EnvironmentSystems, ARejectedMapLeavesNoSourcesAndItsMessage) {
  PENUMBRA_STABILITY("a map with a NaN texel in the ECS",
                     "no sources (SH alone), the message names the map; not retried every frame",
                     "-");
  Fixture f;
  f.world.emplace_resource<EnvironmentLight>();
  auto m = t::flat_map(64, 32, glm::vec3(0.3f));
  m.source = "bad_sky.exr";
  m.rgb[3 * 40] = std::numeric_limits<float>::quiet_NaN();
  f.set_map(m);
  f.executor.run(f.schedule, f.world);
  const EnvironmentLight& l = f.world.resource<EnvironmentLight>();
  EXPECT_TRUE(l.sources.empty());
  EXPECT_EQ(l.sources_version, l.version);  // not retried every frame
  EXPECT_NE(f.world.resource<env::EnvironmentSettings>().error.find("bad_sky.exr"),
            std::string::npos)
      << f.world.resource<env::EnvironmentSettings>().error;
}

TEST(EnvironmentSystems, NoEnvironmentNothingToDo) {
  Fixture f;
  f.executor.run(f.schedule, f.world);
  EXPECT_EQ(f.world.resource<env::EnvironmentSettings>().detections, 0u);
}

}  // namespace
