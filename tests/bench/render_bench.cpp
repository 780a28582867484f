// Benchmark group "render": frame time of the Vulkan renderer on this machine's device
// (lavapipe here and in CI) at 960x540 for a 256x256 terrain with a 256x256 lighting texture,
// 50 per-vertex-lit meshes (1,024 triangles each) and the procedural sky, with the GPU time of
// every pass (timestamps). Validation layers off.
//
//   frame          render() back to back, 2 frames in flight: the throughput frame time
//   frame_lod0     the same with the terrain at full detail (no level of detail; the default
//                  budget is 3 pixels of geometric error, render/terrain_pass.h)
//   frame_latency  render() + wait for that frame
//   terrain_only / meshes_only   one scene pass enabled (plus sky-less clear and tonemap)
//   empty          clear + tonemap + output: a full-screen pass of the cheapest shader here
//   bintree_build / bintree_triangulate   the terrain level of detail on the CPU
//                  (render/terrain_bintree.h) for a 257x257 field: the exact errors, redone on
//                  the render thread whenever the heights change, and the per-frame refinement
//                  from a demo-like view at 3 pixels; reported against the frame time
//
// Floor: pixels shaded / fill rate. Every pixel is shaded at least once by the scene (terrain,
// mesh or sky) and once by the tonemap, and the fill rate is measured on the tonemap pass of
// the empty frame (W*H pixels / its GPU time): floor = 2 * W*H / fill rate. Triangle setup is
// not in that floor: the summary reports the per-triangle cost measured between frame_lod0 and
// frame (same pixels, different triangle counts).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bench_registry.h"
#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/terrain_bintree.h"

namespace {
namespace pb = penumbra::bench;
namespace render = penumbra::render;
namespace data = penumbra::data;

constexpr std::uint32_t kWidth = 960, kHeight = 540;
constexpr int kTerrain = 256;
constexpr int kMeshes = 50;
constexpr double kMinTime = 2.0;

float height_at(float x, float y) {
  return 8.0f * std::sin(0.05f * x) * std::cos(0.04f * y) + 2.0f * std::sin(0.13f * x + 0.09f * y);
}

std::shared_ptr<data::MeshData> uv_sphere(int stacks, int slices, float radius) {
  auto m = std::make_shared<data::MeshData>();
  for (int i = 0; i <= stacks; ++i) {
    const float theta = 3.14159265f * static_cast<float>(i) / static_cast<float>(stacks);
    for (int j = 0; j <= slices; ++j) {
      const float phi = 6.2831853f * static_cast<float>(j) / static_cast<float>(slices);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                        std::cos(theta));
      m->positions.push_back(radius * n);
      m->normals.push_back(n);
    }
  }
  const auto row = static_cast<std::uint32_t>(slices + 1);
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(stacks); ++i)
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
      const std::uint32_t a = i * row + j, b = a + 1, c = a + row, d = c + 1;
      m->indices.insert(m->indices.end(), {a, c, b, b, c, d});  // counter-clockwise from outside
    }
  return m;
}

render::RenderPacket bench_scene() {
  render::RenderPacket p;
  auto field = std::make_shared<data::HeightField>();
  field->width = field->height = kTerrain;
  field->cell_size = 1.0f;
  const float half = 0.5f * (kTerrain - 1);
  for (int y = 0; y < kTerrain; ++y)
    for (int x = 0; x < kTerrain; ++x)
      field->heights.push_back(
          height_at(static_cast<float>(x) - half, static_cast<float>(y) - half));
  auto lighting = std::make_shared<std::vector<glm::vec3>>();
  const glm::vec3 sun = glm::normalize(p.sky.sun_direction);
  for (int y = 0; y < kTerrain; ++y)
    for (int x = 0; x < kTerrain; ++x) {
      const float dx =
          field->at(std::min(x + 1, kTerrain - 1), y) - field->at(std::max(x - 1, 0), y);
      const float dy =
          field->at(x, std::min(y + 1, kTerrain - 1)) - field->at(x, std::max(y - 1, 0));
      const glm::vec3 n = glm::normalize(glm::vec3(-dx, -dy, 2.0f));
      lighting->push_back(glm::vec3(1.2f * std::max(glm::dot(n, sun), 0.0f) + 0.3f));
    }
  p.terrain = {field, {-half, -half, 0.0f}, glm::vec3(0.5f), lighting, kTerrain, kTerrain};

  auto sphere = uv_sphere(16, 32, 4.0f);  // 561 vertices, 1,024 triangles
  for (int i = 0; i < kMeshes; ++i) {
    const float x = -90.0f + 20.0f * static_cast<float>(i % 10);
    const float y = -40.0f + 20.0f * static_cast<float>(i / 10);
    render::MeshDraw d;
    d.mesh = sphere;
    d.transform = glm::translate(glm::mat4(1.0f), {x, y, height_at(x, y) + 6.0f});
    d.albedo = glm::vec3(0.8f);
    auto light = std::make_shared<std::vector<glm::vec3>>();
    for (const glm::vec3& n : sphere->normals) light->push_back(1.5f * (0.5f * n + 0.5f));
    d.vertex_lighting = light;
    p.meshes.push_back(d);
  }
  p.camera.position = {0.0f, -170.0f, 70.0f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.9f;
  return p;
}

struct Bench {
  render::Instance instance{[] {
    render::InstanceConfig c;
    c.app_name = "bench_render";
    c.validation = false;
    return c;
  }()};
  render::Device device{instance};
  render::Renderer renderer{device};
  render::OffscreenTarget target{kWidth, kHeight};
  render::RenderPacket scene = bench_scene();
};
std::unique_ptr<Bench> g_bench;
Bench& bench() {
  if (!g_bench) g_bench = std::make_unique<Bench>();
  return *g_bench;
}

enum class Variant { kFrame, kLod0, kLatency, kTerrainOnly, kMeshesOnly, kEmpty };

void BM_Render(benchmark::State& state, Variant v) {
  Bench& b = bench();
  render::RenderPacket p = b.scene;
  if (v == Variant::kLod0) p.view.terrain_lod_pixels = 0.0f;
  if (v == Variant::kTerrainOnly || v == Variant::kMeshesOnly || v == Variant::kEmpty) {
    p.view.sky = p.view.debug = false;
    p.view.terrain = v == Variant::kTerrainOnly;
    p.view.meshes = v == Variant::kMeshesOnly;
  }
  for (int i = 0; i < 3; ++i) b.renderer.render(p, b.target);  // warm: uploads, caches
  b.renderer.wait_idle();
  b.renderer.pass_table().clear();
  for (auto _ : state) {
    b.renderer.render(p, b.target);
    if (v == Variant::kLatency) b.renderer.wait_idle();
  }
  b.renderer.wait_idle();
  const render::PassTimingTable& t = b.renderer.pass_table();
  for (const auto& row : t.rows()) state.counters["gpu_" + row.name + "_ms"] = t.mean_ms(row.name);
  state.counters["gpu_frame_ms"] = t.mean_total_ms();
  const auto stats = b.renderer.stats();
  state.counters["terrain_triangles"] = static_cast<double>(stats.terrain_triangles);
  state.counters["mesh_triangles"] = static_cast<double>(stats.mesh_triangles);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(b.device.name());
}

// 257 x 257 samples (2^k + 1, as the demo's crop), the frame benchmark's hills at 2 m cells.
data::HeightField bintree_field() {
  data::HeightField f;
  f.width = f.height = 257;
  f.cell_size = 2.0f;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      f.heights.push_back(height_at(static_cast<float>(x), static_cast<float>(y)));
  return f;
}

void BM_BintreeBuild(benchmark::State& state) {
  const data::HeightField f = bintree_field();
  render::TerrainBintree tree;
  for (auto _ : state) {
    tree.build(f);
    benchmark::DoNotOptimize(tree.size());
  }
}

void BM_BintreeTriangulate(benchmark::State& state) {
  const data::HeightField f = bintree_field();
  render::TerrainBintree tree;
  tree.build(f);
  // Seen from beside and above, as the demo's orbit sees its terrain.
  render::TerrainBintree::View view;
  const glm::vec3 centre(256.0f, 256.0f, 0.0f);
  view.eye = centre + glm::vec3(0.0f, -0.85f * 512.0f, 0.45f * 512.0f);
  view.view_proj = glm::perspective(0.8f, 960.0f / 540.0f, 1.0f, 1e4f) *
                   glm::lookAt(view.eye, centre, glm::vec3(0, 0, 1));
  view.view_proj[1][1] *= -1.0f;  // Vulkan clip y
  view.focal_px = 0.5f * 540.0f / std::tan(0.4f);
  view.max_pixels = 3.0f;
  std::vector<std::uint32_t> indices;
  std::size_t triangles = 0;
  for (auto _ : state) {
    indices.clear();
    triangles = tree.triangulate(view, indices);
    benchmark::DoNotOptimize(indices.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}

const std::map<Variant, const char*> kNames = {{Variant::kFrame, "frame"},
                                               {Variant::kLod0, "frame_lod0"},
                                               {Variant::kLatency, "frame_latency"},
                                               {Variant::kTerrainOnly, "terrain_only"},
                                               {Variant::kMeshesOnly, "meshes_only"},
                                               {Variant::kEmpty, "empty"}};

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  auto ms = [&](const char* key) { return pb::scale(r.real_ns(key), 1e-6); };
  auto gpu = [&](const char* key, const std::string& pass) {
    return r.counter(key, "gpu_" + pass + "_ms");
  };
  const double pixels = double{kWidth} * kHeight;
  const auto frame = ms("frame");
  const auto tonemap_empty = gpu("empty", "tonemap");
  const auto fill = pb::quotient(std::optional<double>(pixels * 1e-3), tonemap_empty);  // Mpix/s
  const auto pixel_floor = pb::scale(tonemap_empty, 2.0);

  {
    pb::Row row;
    row.name = "frame 960x540: terrain 256^2 + 50 meshes";
    row.unit = "ms";
    row.value = frame;
    row.goal = pb::Goal::value_at_most(1000.0 / 30.0);
    row.floor = pixel_floor;
    row.floor_ratio = pb::quotient(frame, pixel_floor);
    char note[256];
    std::snprintf(note, sizeof note,
                  "%.0f fps; %.0f terrain + %.0f mesh triangles; floor = 2 x W*H / fill rate "
                  "(scene + tonemap pixels)",
                  frame ? 1000.0 / *frame : 0.0,
                  r.counter("frame", "terrain_triangles").value_or(0),
                  r.counter("frame", "mesh_triangles").value_or(0));
    row.note = note;
    s.add(row);
  }
  for (const char* pass : {"upload", "terrain", "meshes", "debug", "sky", "tonemap", "output"}) {
    pb::Row row;
    row.name = std::string("  gpu pass: ") + pass;
    row.unit = "ms";
    row.value = gpu("frame", pass);
    row.baseline = gpu("frame", "frame");
    row.ratio = pb::quotient(row.value, row.baseline);
    row.ratio_def = "share of the GPU frame";
    s.add(row);
  }
  s.add_vs_baseline("terrain LOD (3 px error) vs full detail", "ms", frame, ms("frame_lod0"),
                    pb::Goal::none(), std::nullopt, "baseline = frame with terrain_lod_pixels 0");
  {
    const auto t0 = gpu("frame_lod0", "terrain"), t1 = gpu("frame", "terrain");
    const auto n0 = r.counter("frame_lod0", "terrain_triangles");
    const auto n1 = r.counter("frame", "terrain_triangles");
    pb::Row row;
    row.name = "terrain cost per triangle (full - LOD)";
    row.unit = "ns/tri";
    if (t0 && t1 && n0 && n1 && *n0 > *n1) row.value = (*t0 - *t1) * 1e6 / (*n0 - *n1);
    row.note = "GPU terrain-pass time difference over triangle-count difference, same pixels";
    s.add(row);
  }
  s.add_vs_baseline("frame latency (render + wait)", "ms", ms("frame_latency"), frame,
                    pb::Goal::none(), std::nullopt, "baseline = pipelined frame (2 in flight)");
  s.add_vs_baseline("terrain only (+ clear, tonemap)", "ms", ms("terrain_only"), frame,
                    pb::Goal::none());
  s.add_vs_baseline("meshes only (+ clear, tonemap)", "ms", ms("meshes_only"), frame,
                    pb::Goal::none());
  s.add_vs_baseline("empty frame (clear + tonemap)", "ms", ms("empty"), frame, pb::Goal::none());
  s.add_vs_baseline("terrain bintree build 257^2 (per height change)", "ms", ms("bintree_build"),
                    frame, pb::Goal::none(), std::nullopt,
                    "render thread, once per change of the heights; ratio = frame / build");
  {
    char note[128];
    std::snprintf(note, sizeof note, "%.0f triangles at 3 px; ratio = frame / triangulate",
                  r.counter("bintree_triangulate", "triangles").value_or(0));
    s.add_vs_baseline("terrain bintree triangulate (per frame)", "ms", ms("bintree_triangulate"),
                      frame, pb::Goal::none(), std::nullopt, note);
  }
  {
    pb::Row row;
    row.name = "fill rate (tonemap, empty frame)";
    row.unit = "Mpixel/s";
    row.value = fill;
    row.note = "W*H / GPU time of the tonemap pass (the cheapest full-screen shader here)";
    s.add(row);
  }
  return s;
}

void register_benchmarks() {
  // Frames: wall clock (the device works on other threads); the bintree: CPU time, one thread.
  for (const auto& [variant, name] : kNames)
    pb::add(name, {.unit = benchmark::kMillisecond, .min_time = kMinTime}, BM_Render, variant);
  const pb::Timing cpu{.clock = pb::Timing::Clock::kCpu, .unit = benchmark::kMillisecond};
  pb::add("bintree_build", cpu, BM_BintreeBuild);
  pb::add("bintree_triangulate", cpu, BM_BintreeTriangulate);
}

}  // namespace

int main(int argc, char** argv) {
  return pb::run_group(argc, argv, "render", register_benchmarks, summarize,
                       [] { g_bench.reset(); });
}
