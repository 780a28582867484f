#include "penumbra/systems/render_extract/render_extract.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/material.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/jobs/executor.h"
#include "render_test_util.h"

namespace penumbra::systems {
namespace {
using namespace components;

TEST(RenderExtract, BuildsThePacketFromComponentsSharingArrays) {
  ecs::World w;
  emplace_render_resources(w);
  w.emplace_resource<Camera>().position = {1, 2, 3};
  w.resource<RenderSettings>().view.exposure_ev = 1.5f;
  auto mesh = render::test::make_uv_sphere(4, 8, 1.0f);
  auto lighting = std::make_shared<std::vector<glm::vec3>>(mesh->positions.size(), glm::vec3(2));
  const ecs::Entity lit =
      w.create_with(Transform{glm::mat4(2.0f)}, MeshInstance{mesh},
                    BaseColor{{0.1f, 0.2f, 0.3f, 1.0f}}, VertexLighting{lighting});
  w.create_with(Transform{}, MeshInstance{mesh});  // no colour: the mesh's base colour
  w.create_with(Transform{}, MeshInstance{});      // no mesh: skipped
  auto heights = render::test::make_hills(8, 1.0f);
  auto texels = std::make_shared<std::vector<glm::vec3>>(64, glm::vec3(1));
  w.create_with(Terrain{heights, {1, 1, 0}, glm::vec3(0.7f)},
                TerrainLighting{texels, 8, 8, nullptr});
  w.create_with(DebugSphere{{0, 0, 5}, 2.0f, {1, 0, 0}});
  w.create_with(DebugLines{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 1}}}});
  w.create_with(DebugLines{{{{0, 0, 0}, {0, 0, 1}, {1, 1, 1}}}},
                DebugPoints{{{{1, 2, 3}, {0, 1, 0}}}});

  jobs::Schedule s;
  add_render_extract(s);
  jobs::Executor ex(1);
  ex.run(s, w);
  const render::RenderPacket& p = w.resource<render::RenderPacket>();
  EXPECT_EQ(p.camera.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(p.view.exposure_ev, 1.5f);
  ASSERT_EQ(p.meshes.size(), 2u);
  const render::MeshDraw& d = p.meshes[0].vertex_lighting ? p.meshes[0] : p.meshes[1];
  EXPECT_EQ(d.vertex_lighting.get(), lighting.get()) << "shared, not copied";
  EXPECT_EQ(d.albedo, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(d.transform, glm::mat4(2.0f));
  EXPECT_EQ(d.mesh.get(), mesh.get());
  EXPECT_EQ(p.terrain.heights.get(), heights.get());
  EXPECT_EQ(p.terrain.lighting.get(), texels.get());
  EXPECT_EQ(p.terrain.lighting_width, 8);
  ASSERT_EQ(p.spheres.size(), 1u);
  EXPECT_EQ(p.spheres[0].radius, 2.0f);
  EXPECT_EQ(p.lines.size(), 3u) << "every entity's lines";
  ASSERT_EQ(p.points.size(), 1u);
  EXPECT_EQ(p.points[0].position, glm::vec3(1, 2, 3));

  w.destroy(lit);
  ex.run(s, w);
  EXPECT_EQ(w.resource<render::RenderPacket>().meshes.size(), 1u) << "rebuilt every frame";
}

TEST(RenderExtract, ScalesTerrainHeightsOncePerChange) {
  ecs::World w;
  emplace_render_resources(w);
  auto heights = render::test::make_hills(8, 1.0f);
  const ecs::Entity e = w.create_with(Terrain{heights, {0, 0, 0}, glm::vec3(0.5f), 2.5f});
  ScaledHeightsCache cache;
  render::RenderPacket p;
  extract_render_packet(w, p, &cache);
  ASSERT_NE(p.terrain.heights.get(), heights.get());
  EXPECT_FLOAT_EQ(p.terrain.heights->at(3, 4), 2.5f * heights->at(3, 4));
  const auto first = p.terrain.heights;
  extract_render_packet(w, p, &cache);
  EXPECT_EQ(p.terrain.heights, first) << "cached while heights and scale are unchanged";
  w.get_mut<Terrain>(e)->height_scale = 1.0f;
  extract_render_packet(w, p, &cache);
  EXPECT_EQ(p.terrain.heights.get(), heights.get()) << "scale 1 shares the heights";
}

// An EnvironmentLight with two detected sources: a narrow sun (source 0) and a wide lamp
// (source 1), and the four OEM sets (set i: every value i + channel / 10 + coefficient / 100).
EnvironmentLight two_sources() {
  EnvironmentLight env;
  env.version = env.sources_version = 4;
  env.rotation_z = 1.5707963f;
  env.sources.push_back({{1, 0, 0}, 0.01f, glm::vec3(50), {5, 4, 3}, 0.3f});
  env.sources.push_back({{0, 0, 1}, 0.5f, glm::vec3(2), {1, 1, 1}, 0.2f});
  for (int set = 0; set < 4; ++set) {
    sh::CoeffsRgb<3> s3{};
    sh::CoeffsRgb<sh::kDefaultBands> s4{};
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 9; ++i) s3[c][i] = s4[c][i] = set + 0.1f * c + 0.01f * i;
    env.oem_sh3.push_back(s3);
    env.oem_sh.push_back(s4);
  }
  return env;
}

TEST(RenderExtract, EnvironmentShadingIsOptIn) {
  ecs::World w;
  emplace_render_resources(w);
  w.emplace_resource<EnvironmentLight>(two_sources());
  render::RenderPacket p;
  extract_render_packet(w, p);
  EXPECT_FALSE(p.environment.enabled);
  EXPECT_TRUE(p.environment.sources.empty());
}

TEST(RenderExtract, EnvironmentShadingFromTheSources) {
  ecs::World w;
  emplace_render_resources(w);
  EnvironmentShadingSettings& settings = w.resource<RenderSettings>().environment;
  settings.enabled = true;
  settings.weight[0] = 0.5f;
  settings.direct_diffuse = false;
  w.emplace_resource<EnvironmentLight>(two_sources());
  render::RenderPacket p;
  extract_render_packet(w, p);
  const render::EnvironmentShading& e = p.environment;
  EXPECT_TRUE(e.enabled);
  EXPECT_FALSE(e.direct_diffuse);
  ASSERT_EQ(e.sources.size(), 1u) << "the wide source stays in the SH";
  EXPECT_EQ(e.sources[0].oem_bit, 0u);
  EXPECT_NEAR(e.sources[0].direction.y, 1.0f, 1e-6f) << "turned by rotation_z";
  EXPECT_EQ(e.sources[0].irradiance, glm::vec3(5, 4, 3));
  EXPECT_EQ(e.sources[0].weight, 0.5f);
  EXPECT_EQ(e.present_mask, 0b10u);
  EXPECT_EQ(e.oem_source_count, 2u);
  EXPECT_FLOAT_EQ(e.rotation_z, 1.5707963f);
  ASSERT_TRUE(e.oem_sh);
  ASSERT_EQ(e.oem_sh->size(), 4u * 27u);
  EXPECT_FLOAT_EQ((*e.oem_sh)[2 * 27 + 1 * 9 + 5], 2.15f) << "set 2, green, coefficient 5";
  const auto first = e.oem_sh;
  extract_render_packet(w, p);
  EXPECT_EQ(p.environment.oem_sh, first) << "re-packed only when the map changes";
  EnvironmentLight& env = w.resource<EnvironmentLight>();
  env.version = env.sources_version = 5;
  extract_render_packet(w, p);
  EXPECT_NE(p.environment.oem_sh, first);
  // A map whose sources are not found yet (sources_version behind): no sources, today's path.
  env.version = 6;
  extract_render_packet(w, p);
  EXPECT_TRUE(p.environment.sources.empty());
  // No EnvironmentLight at all: likewise.
  ecs::World bare;
  emplace_render_resources(bare);
  bare.resource<RenderSettings>().environment.enabled = true;
  extract_render_packet(bare, p);
  EXPECT_TRUE(p.environment.sources.empty());
}

TEST(RenderExtract, MaterialPhongExponentGivesTheBlinnLobe) {
  ecs::World w;
  auto mesh = render::test::make_uv_sphere(4, 8, 1.0f);
  w.create_with(Transform{}, MeshInstance{mesh}, Material{glm::vec3(0.5f), 16.0f});
  render::RenderPacket p;
  extract_render_packet(w, p);
  ASSERT_EQ(p.meshes.size(), 1u);
  EXPECT_EQ(p.meshes[0].specular_exponent, 64.0f);
}

TEST(RenderExtract, OrdersAfterWritersOfItsInputs) {
  jobs::Schedule s;
  s.add_each<Transform>("move", [](Transform& t) { t.world[3][0] += 1; });
  s.add_task("probe_lines", [](jobs::SystemContext&) {}).writes<DebugLines>();
  add_render_extract(s);
  s.add_task("present", [](jobs::SystemContext&) {}).reads<render::RenderPacket>();
  s.build();
  auto index = [&](const std::string& name) {
    for (std::size_t i = 0; i < s.nodes().size(); ++i)
      if (s.nodes()[i].system->name == name) return static_cast<std::uint32_t>(i);
    return ~0u;
  };
  auto edge = [&](const std::string& a, const std::string& b) {
    const auto& succ = s.nodes()[index(a)].successors;
    return std::find(succ.begin(), succ.end(), index(b)) != succ.end();
  };
  EXPECT_TRUE(edge("move", "render_extract")) << s.to_dot();
  EXPECT_TRUE(edge("probe_lines", "render_extract")) << "debug geometry arrives as components";
  EXPECT_TRUE(edge("render_extract", "present")) << s.to_dot();
}

}  // namespace
}  // namespace penumbra::systems
