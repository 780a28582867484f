#include "penumbra/systems/render_extract/render_extract.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "penumbra/components/camera.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/lighting_result.h"
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
