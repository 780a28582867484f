// Shared by the render tests: a validated lavapipe context, golden-image checks and small scenes.
//
// Every test that needs Vulkan creates a TestContext, which throws (so the test FAILS, never
// skips) when no Vulkan device can be created. Validation is required (VK_LAYER_KHRONOS_validation
// from vulkan-validationlayers); tests assert that no validation message was reported.
//
// Golden images live in tests/render/golden/NAME.png. A test writes what it rendered to
// <build>/tests/render/output/NAME.png; when the comparison fails it also writes NAME.diff.png
// next to it. Goldens are (re)written only when PENUMBRA_UPDATE_GOLDEN=1 is set.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/render/device.h"
#include "penumbra/render/image.h"
#include "penumbra/render/instance.h"
#include "penumbra/render/packet.h"

namespace penumbra::render::test {

// Tolerance of the golden comparisons: a pixel differs when a channel is off by more than
// kGoldenTolerance 8-bit steps; a comparison fails when more than kGoldenMaxFraction of the
// pixels differ (rasterisation and LLVM code generation may move a few edge pixels between
// Mesa versions; shading changes move many).
constexpr int kGoldenTolerance = 3;
constexpr double kGoldenMaxFraction = 0.005;

inline InstanceConfig validated_config() {
  InstanceConfig c;
  c.app_name = "penumbra-tests";
  c.validation = true;
  c.require_validation = true;
  c.synchronization_validation = true;
  return c;
}

struct TestContext {
  Instance instance{validated_config()};
  Device device{instance};
};

inline std::string output_dir() {
  const std::string dir = PENUMBRA_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  return dir;
}

inline bool update_golden() {
  const char* v = std::getenv("PENUMBRA_UPDATE_GOLDEN");
  return v != nullptr && std::string(v) == "1";
}

inline void expect_matches_golden(const ImageRgba8& image, const std::string& name) {
  // Appended: string(...) + "/" + ... makes gcc 12 warn in libstdc++ (tests/CMakeLists.txt, PCH).
  std::string golden = PENUMBRA_GOLDEN_DIR "/";
  golden += name + ".png";
  const std::string actual = output_dir() + "/" + name + ".png";
  write_png(actual, image);
  if (update_golden()) {
    write_png(golden, image);
    std::printf("updated golden image %s\n", golden.c_str());
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(golden))
      << "missing golden image " << golden << " (rendered: " << actual
      << "); create it with PENUMBRA_UPDATE_GOLDEN=1 after checking the rendered image";
  const ImageComparison c = compare_images(image, read_png(golden), kGoldenTolerance);
  ASSERT_TRUE(c.same_size) << name << ": size differs from " << golden;
  if (c.fraction() > kGoldenMaxFraction) {
    const std::string diff = output_dir() + "/" + name + ".diff.png";
    write_png(diff, c.diff);
    ADD_FAILURE() << name << ": " << c.differing << " of " << c.pixels << " pixels ("
                  << 100.0 * c.fraction() << "%) differ by more than " << kGoldenTolerance
                  << " (max " << c.max_difference << "); allowed " << 100.0 * kGoldenMaxFraction
                  << "%\n  rendered: " << actual << "\n  golden:   " << golden
                  << "\n  diff:     " << diff;
  }
}

// --- Scenes ---------------------------------------------------------------------------------

inline std::shared_ptr<data::MeshData> make_uv_sphere(int stacks, int slices, float radius) {
  auto m = std::make_shared<data::MeshData>();
  m->name = "uv_sphere";
  for (int i = 0; i <= stacks; ++i) {
    const float theta = 3.14159265f * static_cast<float>(i) / static_cast<float>(stacks);
    for (int j = 0; j <= slices; ++j) {
      const float phi = 2.0f * 3.14159265f * static_cast<float>(j) / static_cast<float>(slices);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                        std::cos(theta));
      m->positions.push_back(radius * n);
      m->normals.push_back(n);
    }
  }
  const auto row = static_cast<std::uint32_t>(slices + 1);
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(stacks); ++i) {
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
      const std::uint32_t a = i * row + j, b = a + 1, c = a + row, d = c + 1;
      m->indices.insert(m->indices.end(), {a, c, b, b, c, d});  // counter-clockwise from outside
    }
  }
  return m;
}

// Per-vertex colours from the normal direction (a recognisable rainbow ball).
inline std::shared_ptr<std::vector<glm::vec3>> normal_colours(const data::MeshData& m,
                                                              float scale) {
  auto c = std::make_shared<std::vector<glm::vec3>>();
  for (const glm::vec3& n : m.normals) c->push_back(scale * (0.5f * n + 0.5f));
  return c;
}

inline std::shared_ptr<data::HeightField> make_hills(int size, float cell) {
  auto f = std::make_shared<data::HeightField>();
  f->width = f->height = size;
  f->cell_size = cell;
  f->source = "test hills";
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      f->heights.push_back(1.5f * std::sin(0.35f * static_cast<float>(x)) *
                               std::cos(0.25f * static_cast<float>(y)) +
                           0.05f * static_cast<float>(x));
  return f;
}

// Lighting with structure a sampling error would show: a warm/cool gradient and a dark band.
inline std::shared_ptr<std::vector<glm::vec3>> make_lighting(int w, int h) {
  auto l = std::make_shared<std::vector<glm::vec3>>();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float u = static_cast<float>(x) / static_cast<float>(w - 1);
      const float v = static_cast<float>(y) / static_cast<float>(h - 1);
      const float shadow = (x > w / 3 && x < w / 2) ? 0.2f : 1.0f;
      l->push_back(shadow * glm::vec3(1.5f * u + 0.2f, 0.8f, 1.5f * v + 0.2f));
    }
  }
  return l;
}

inline RenderPacket terrain_scene() {
  RenderPacket p;
  p.terrain.heights = make_hills(32, 1.0f);
  p.terrain.origin = {-15.5f, -15.5f, 0.0f};
  p.terrain.albedo = glm::vec3(0.8f);
  p.terrain.lighting = make_lighting(32, 32);
  p.terrain.lighting_width = p.terrain.lighting_height = 32;
  p.camera.position = {0.0f, -30.0f, 16.0f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.9f;
  return p;
}

inline RenderPacket mesh_scene() {
  RenderPacket p;
  auto sphere = make_uv_sphere(12, 24, 1.0f);
  MeshDraw lit;
  lit.mesh = sphere;
  lit.transform = glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f, 0.0f, 0.0f));
  lit.vertex_lighting = normal_colours(*sphere, 1.0f);
  p.meshes.push_back(lit);
  MeshDraw preview;  // no lighting: the fixed sun + sky preview
  preview.mesh = sphere;
  preview.albedo = {0.9f, 0.6f, 0.3f};
  preview.transform =
      glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(1.3f, 0.0f, 0.0f)), glm::vec3(0.8f));
  p.meshes.push_back(preview);
  p.camera.position = {0.0f, -6.0f, 1.5f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.7f;
  return p;
}

inline RenderPacket debug_scene() {
  RenderPacket p;
  p.view.sky = false;
  p.spheres.push_back({{-1.5f, 0.0f, 0.0f}, 1.0f, {1.0f, 0.3f, 0.2f}});
  p.spheres.push_back({{1.2f, 0.5f, 0.3f}, 0.7f, {0.2f, 0.9f, 0.3f}});
  const glm::vec3 t[4] = {{0, 0, 1.5f}, {-1, -1, -0.5f}, {1, -1, -0.5f}, {0, 1, -0.5f}};
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) p.lines.push_back({t[i], t[j], {0.3f, 0.5f, 1.0f}});
  for (int i = 0; i < 4; ++i) p.points.push_back({t[i], {1.0f, 1.0f, 0.2f}});
  p.view.point_size = 3.0f;
  p.camera.position = {0.0f, -6.0f, 1.0f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.9f;
  return p;
}

// A small equirectangular map: blue sky with a bright spot at azimuth 90 degrees (+y),
// elevation 30 degrees, and a brown ground.
inline std::shared_ptr<data::EnvironmentMap> make_environment(int w, int h) {
  auto e = std::make_shared<data::EnvironmentMap>();
  e->width = w;
  e->height = h;
  e->source = "test environment";
  for (int y = 0; y < h; ++y) {
    const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(h);
    for (int x = 0; x < w; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(w);
      glm::vec3 c =
          v < 0.5f ? glm::vec3(0.2f, 0.4f, 1.0f) * (1.2f - v) : glm::vec3(0.3f, 0.2f, 0.1f);
      if (std::abs(u - 0.25f) < 0.04f && std::abs(v - 0.333f) < 0.06f) c = glm::vec3(8.0f);
      e->rgb.insert(e->rgb.end(), {c.x, c.y, c.z});
    }
  }
  return e;
}

inline RenderPacket environment_scene() {
  RenderPacket p;
  p.sky.environment = make_environment(64, 32);
  p.camera.position = {0.0f, 0.0f, 0.0f};
  p.camera.target = {0.0f, 1.0f, 0.3f};  // looking at +y, slightly up: the bright spot
  p.camera.vertical_fov = 1.2f;
  return p;
}

}  // namespace penumbra::render::test
