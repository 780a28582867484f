// The environment shading (shadow_pass.h, shaders/mesh.glsl MESH_ENVIRONMENT): the shadow box,
// the packet check, the OEM sets, and lavapipe renders (golden, acne, OEM subset, bad input).
#include "penumbra/render/shadow_pass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "common/stability.h"
#include "penumbra/render/camera.h"
#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/projection.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

constexpr std::uint32_t kWidth = 128, kHeight = 72;

// A closed box centred at the origin (24 vertices, normals per face, counter-clockwise from
// outside).
std::shared_ptr<data::MeshData> make_box(glm::vec3 half) {
  auto m = std::make_shared<data::MeshData>();
  m->name = "box";
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 n(0.0f);
      n[axis] = sign;
      const glm::vec3 u = axis == 2 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
      const glm::vec3 v = glm::cross(n, u);
      const auto base = static_cast<std::uint32_t>(m->positions.size());
      for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        m->positions.push_back(half * (n + c.x * u + c.y * v));
        m->normals.push_back(n);
      }
      // u x v = n x ... : (u, v, n) is right-handed, so (0, 1, 2) turns counter-clockwise about n.
      m->indices.insert(m->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

// One set per subset: every coefficient zero except L_00 = rgb / y_00 (a constant radiance).
std::shared_ptr<std::vector<float>> constant_sets(const std::vector<glm::vec3>& radiance) {
  auto sets = std::make_shared<std::vector<float>>(radiance.size() * 27, 0.0f);
  for (std::size_t i = 0; i < radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) (*sets)[i * 27 + c * 9] = radiance[i][c] / 0.282094792f;
  return sets;
}

EnvironmentShading one_source(glm::vec3 direction, glm::vec3 irradiance) {
  EnvironmentShading e;
  e.enabled = true;
  e.sources.push_back({direction, irradiance, 0, 1.0f});
  e.oem_source_count = 1;
  e.oem_sh = constant_sets({glm::vec3(0.05f), glm::vec3(0.3f)});
  e.shadow_map_size = 512;
  return e;
}

// A slab ground (10 x 10 m, `thickness` thick, top at z = 0) and, optionally, a sphere above it.
RenderPacket ground_scene(bool sphere, float thickness = 0.1f) {
  RenderPacket p;
  MeshDraw ground;
  ground.mesh = make_box({5.0f, 5.0f, 0.5f * thickness});
  ground.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.5f * thickness));
  ground.albedo = glm::vec3(0.8f);
  p.meshes.push_back(ground);
  if (sphere) {
    MeshDraw ball;
    ball.mesh = test::make_uv_sphere(16, 32, 0.7f);
    ball.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.0f));
    ball.albedo = {0.9f, 0.5f, 0.3f};
    ball.specular_exponent = 64.0f;
    p.meshes.push_back(ball);
  }
  p.camera.position = {0.0f, -5.0f, 3.0f};
  p.camera.target = {0.0f, 0.0f, 0.5f};
  p.camera.vertical_fov = 0.9f;
  p.view.sky = false;
  return p;
}

// The pixel (column, row) where world point w lands.
glm::ivec2 pixel_of(const RenderPacket& p, glm::vec3 w) {
  const glm::vec4 c = view_projection(p.camera, float(kWidth) / float(kHeight)) * glm::vec4(w, 1);
  const glm::vec2 ndc = glm::vec2(c) / c.w;
  return {int((0.5f * ndc.x + 0.5f) * kWidth), int((0.5f * ndc.y + 0.5f) * kHeight)};
}

glm::ivec3 rgb_at(const ImageRgba8& image, glm::ivec2 px) {
  const std::size_t i = (std::size_t(px.y) * image.width + px.x) * 4;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

int srgb8(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return int(std::lround(255.0f * s));
}

struct Gpu {
  test::TestContext ctx;
  Renderer renderer{ctx.device};
  OffscreenTarget target{kWidth, kHeight};
  ImageRgba8 render(const RenderPacket& p) {
    auto image = renderer.capture(p, target);
    EXPECT_TRUE(image.has_value());
    return image ? *image : ImageRgba8{};
  }
  ~Gpu() { EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary(); }
};

std::size_t differing_pixels(const ImageRgba8& a, const ImageRgba8& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4)
    n += a.pixels[i] != b.pixels[i] || a.pixels[i + 1] != b.pixels[i + 1] ||
         a.pixels[i + 2] != b.pixels[i + 2];
  return n;
}

// --- CPU: the box, the check, the sets ---------------------------------------------------------

TEST(ShadowBox, HoldsTheSceneForAnyDirection) {
  const glm::vec3 lo(-2.0f, -1.0f, 0.0f), hi(3.0f, 1.0f, 2.5f);
  for (glm::vec3 d :
       {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0.3f, -0.2f, 0.9f),
        glm::vec3(0.0f, 1e-7f, 1.0f), glm::vec3(-1, -1, 0.01f)}) {
    const ShadowBox box = fit_shadow_box(lo, hi, d);
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isfinite(box.extent[i]));
      EXPECT_GT(box.extent[i], 0.0f);
    }
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      const glm::vec4 q = box.view_proj * glm::vec4(p, 1.0f);
      EXPECT_NEAR(q.w, 1.0f, 1e-6f);
      EXPECT_GT(q.x, -1.0f);
      EXPECT_LT(q.x, 1.0f);
      EXPECT_GT(q.y, -1.0f);
      EXPECT_LT(q.y, 1.0f);
      EXPECT_GT(q.z, 0.0f);
      EXPECT_LT(q.z, 1.0f);
    }
    // Depth grows away from the source.
    const glm::vec3 mid = 0.5f * (lo + hi), n = glm::normalize(d);
    const float near = (box.view_proj * glm::vec4(mid + 0.1f * n, 1)).z;
    const float far = (box.view_proj * glm::vec4(mid - 0.1f * n, 1)).z;
    EXPECT_LT(near, far);
  }
}

TEST(ShadowBox, DegenerateInputs) {
  PENUMBRA_STABILITY("a shadow box around one point; a zero light direction",
                     "a minimal finite box (0.002 m); an empty box", "-");
  const ShadowBox point = fit_shadow_box(glm::vec3(1.0f), glm::vec3(1.0f), {0, 0, 1});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(point.extent[i], 0.002f, 1e-5f);
  EXPECT_TRUE(std::isfinite(point.view_proj[3][0]));
  const ShadowBox none = fit_shadow_box(glm::vec3(0.0f), glm::vec3(1.0f), glm::vec3(0.0f));
  EXPECT_EQ(none.extent, glm::vec3(0.0f));
}

TEST(CheckEnvironmentShading, NamesTheFieldAndReason) {
  EnvironmentShading e = one_source({0, 0, 1}, glm::vec3(1.0f));
  EXPECT_EQ(check_environment_shading(e), "");
  EnvironmentShading off;  // disabled: nothing to check
  EXPECT_EQ(check_environment_shading(off), "");
  auto bad = e;
  bad.oem_sh = std::make_shared<std::vector<float>>(20, 0.0f);
  EXPECT_EQ(check_environment_shading(bad),
            "environment.oem_sh: 20 floats, expected 54 (2^1 sets x 27)");
  bad = e;
  auto nan = std::make_shared<std::vector<float>>(*e.oem_sh);
  (*nan)[30] = std::numeric_limits<float>::quiet_NaN();
  bad.oem_sh = nan;
  EXPECT_EQ(check_environment_shading(bad), "environment.oem_sh: value 30 is not finite");
  bad = e;
  bad.sources[0].oem_bit = 1;
  EXPECT_EQ(check_environment_shading(bad), "environment.sources[0].oem_bit: 1, expected < 1");
  bad = e;
  bad.sources[0].direction = glm::vec3(0.0f);
  EXPECT_EQ(check_environment_shading(bad), "environment.sources[0].direction: zero or not finite");
  bad = e;
  bad.sources[0].weight = 1.5f;
  EXPECT_NE(check_environment_shading(bad).find("environment.sources[0].weight"),
            std::string::npos);
  bad = e;
  bad.sources[0].irradiance.y = -1.0f;
  EXPECT_NE(check_environment_shading(bad).find("irradiance"), std::string::npos);
  bad = e;
  bad.present_mask = 1;  // the shadowed source's own bit
  EXPECT_NE(check_environment_shading(bad).find("oem_bit: 0 is another source's"),
            std::string::npos);
  bad = e;
  bad.oem_source_count = 0;
  EXPECT_NE(check_environment_shading(bad).find("oem_source_count: 0"), std::string::npos);
}

// Set V of the shader is the OEM with the sources in V present ([Ambrosj16] Algorithm 6) or,
// with the direct term, the OEM without any shadowed source; a weight blends linearly.
TEST(EnvironmentSets, PickTheSubsetAndBlendWeights) {
  EnvironmentShading e;
  e.enabled = true;
  e.oem_source_count = 3;
  // Env source 0 and 2 have shadow maps (sources[0] is env bit 2, sources[1] env bit 0);
  // env source 1 stays in the SH (present_mask).
  e.sources = {{{0, 0, 1}, glm::vec3(1.0f), 2, 1.0f}, {{1, 0, 0}, glm::vec3(1.0f), 0, 1.0f}};
  e.present_mask = 0b010;
  std::vector<glm::vec3> radiance;
  for (int i = 0; i < 8; ++i) radiance.push_back(glm::vec3(float(i), 10.0f * i, 100.0f * i));
  e.oem_sh = constant_sets(radiance);
  e.direct_diffuse = false;
  auto sets = environment_sets(e);
  ASSERT_EQ(sets.size(), 4u * 9u);
  // Set V's L_00 x A_0 / pi (= L_00) over y_00 recovers the constant radiance of its OEM.
  auto radiance_of = [&](std::size_t v) { return sets[v * 9] * 0.282094792f; };
  EXPECT_NEAR(radiance_of(0b00).x, 2.0f, 1e-5f);  // only env 1: index 0b010
  EXPECT_NEAR(radiance_of(0b01).x, 6.0f, 1e-5f);  // sources[0] seen: + env bit 2 -> 0b110
  EXPECT_NEAR(radiance_of(0b10).x, 3.0f, 1e-5f);  // sources[1] seen: + env bit 0 -> 0b011
  EXPECT_NEAR(radiance_of(0b11).x, 7.0f, 1e-4f);
  e.sources[0].weight = 0.25f;  // halfway towards "switched off": 0.25 OEM(on) + 0.75 OEM(off)
  sets = environment_sets(e);
  EXPECT_NEAR(radiance_of(0b01).x, 0.25f * 6.0f + 0.75f * 2.0f, 1e-5f);
  EXPECT_NEAR(radiance_of(0b11).x, 0.25f * 7.0f + 0.75f * 3.0f, 1e-4f);
  e.direct_diffuse = true;
  sets = environment_sets(e);
  for (std::size_t v = 0; v < 4; ++v) EXPECT_NEAR(radiance_of(v).z, 200.0f, 1e-3f);
  // The band constants: l = 1 scaled by 2/3, l = 2 by 1/4.
  auto one = std::make_shared<std::vector<float>>(8 * 27, 1.0f);
  e.oem_sh = one;
  sets = environment_sets(e);
  EXPECT_NEAR(sets[2].x, 2.0f / 3.0f, 1e-6f);
  EXPECT_NEAR(sets[6].x, 0.25f, 1e-6f);
}

// --- GPU ------------------------------------------------------------------------------------

// A sphere on a slab under one source, direct diffuse + Blinn: the sphere's shadow on the
// ground, its highlight; the OEM sets are a real SH projection (the test map's spot).
TEST(EnvironmentShadingGolden, SphereOnGroundUnderOneSource) {
  Gpu gpu;
  RenderPacket p = ground_scene(true);
  const auto map = test::make_environment(64, 32);
  auto dark = std::make_shared<data::EnvironmentMap>(*map);
  for (float& v : dark->rgb) v = std::min(v, 1.5f);  // the spot (8) taken out
  const auto whole = sh::project_equirect<3>(map->rgb.data(), map->width, map->height);
  const auto rest = sh::project_equirect<3>(dark->rgb.data(), dark->width, dark->height);
  auto sets = std::make_shared<std::vector<float>>();
  for (const auto* s : {&rest, &whole})
    for (int c = 0; c < 3; ++c) sets->insert(sets->end(), (*s)[c].begin(), (*s)[c].end());
  p.environment.enabled = true;
  p.environment.oem_sh = sets;
  p.environment.oem_source_count = 1;
  p.environment.rotation_z = -1.2f;  // the spot (map azimuth 90 degrees) to azimuth about 21
  const float az = 1.5708f - 1.2f, el = 0.5236f;
  p.environment.sources.push_back(
      {{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)},
       glm::vec3(6.0f, 5.5f, 5.0f),
       0,
       1.0f});
  p.environment.shadow_map_size = 512;
  const ImageRgba8 image = gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_maps, 1u);
  EXPECT_EQ(gpu.renderer.stats().environment_error, "");
  test::expect_matches_golden(image, "environment_shadow");
  // The shadow is there: ground behind the sphere (away from the source) darker than beside it.
  const glm::vec3 away = -glm::normalize(glm::vec3(std::cos(az), std::sin(az), 0.0f));
  const glm::ivec3 shadow = rgb_at(image, pixel_of(p, glm::vec3(0, 0, 0) + 1.6f * away));
  const glm::ivec3 lit = rgb_at(image, pixel_of(p, glm::vec3(0, 0, 0) - 1.6f * away));
  EXPECT_LT(shadow.g + 40, lit.g) << "shadow " << shadow.g << " lit " << lit.g;
}

// The slope-scaled bias keeps a lit ground free of acne: with only the source's direct light
// (OEM sets black), every ground pixel has the same value, for a high and a low source. The
// ground is 2 mm thin, so its back faces (what front-face culling stores) lie within a shadow
// texel's depth slope of its top: without the bias this shows acne (checked when the bias
// was set to 0). With a sphere the same setting does show a shadow (the test can fail).
TEST(EnvironmentShading, BiasKeepsALitPlaneFreeOfAcne) {
  Gpu gpu;
  for (float elevation : {1.2f, 0.35f}) {
    RenderPacket p = ground_scene(false, 0.002f);
    p.view.lighting_only = true;
    p.view.tonemap = ViewSettings::Tonemap::kLinear;
    p.environment = one_source({std::cos(elevation), 0.3f, std::sin(elevation)}, glm::vec3(1.5f));
    p.environment.oem_sh = constant_sets({glm::vec3(0.0f), glm::vec3(0.0f)});
    const ImageRgba8 image = gpu.render(p);
    int lo = 255, hi = 0, ground = 0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        const int g = rgb_at(image, {x, y}).g;
        if (g == 0) continue;  // background (no sky drawn)
        ++ground;
        lo = std::min(lo, g);
        hi = std::max(hi, g);
      }
    EXPECT_GT(ground, int(kWidth * kHeight / 2)) << "elevation " << elevation;
    EXPECT_LE(hi - lo, 1) << "elevation " << elevation << ": ground from " << lo << " to " << hi;
  }
  RenderPacket p = ground_scene(true);
  p.view.lighting_only = true;
  p.environment = one_source({0.0f, 0.0f, 1.0f}, glm::vec3(1.5f));  // the zenith
  p.environment.oem_sh = constant_sets({glm::vec3(0.0f), glm::vec3(0.0f)});
  const ImageRgba8 image = gpu.render(p);
  EXPECT_LT(rgb_at(image, pixel_of(p, {0.0f, -0.5f, 0.0f})).g, 5);  // under the sphere
  EXPECT_GT(rgb_at(image, pixel_of(p, {2.0f, -1.0f, 0.0f})).g, 100);
}

// The direct and Blinn terms have their formulas: on a lit glossy ground (OEM sets black,
// lighting-only view, linear tonemap) every pixel is E max(0, n.l) / pi + s (e + 8) / (8 pi)
// (n.h)^e E max(0, n.l), with h from that pixel's view direction.
TEST(EnvironmentShading, DirectAndBlinnTermsMatchTheirFormulas) {
  Gpu gpu;
  RenderPacket p = ground_scene(false);
  p.meshes[0].specular = glm::vec3(0.3f);
  p.meshes[0].specular_exponent = 20.0f;
  p.view.lighting_only = true;
  p.view.tonemap = ViewSettings::Tonemap::kLinear;
  p.camera.position = {0.0f, -6.0f, 3.0f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  const glm::vec3 l = glm::normalize(glm::vec3(0.0f, 1.0f, 0.7f));  // facing the camera
  const glm::vec3 e(0.8f, 0.6f, 0.4f);
  p.environment = one_source(l, e);
  p.environment.oem_sh = constant_sets({glm::vec3(0.0f), glm::vec3(0.0f)});
  const ImageRgba8 image = gpu.render(p);
  const glm::mat4 inv = glm::inverse(view_projection(p.camera, float(kWidth) / float(kHeight)));
  int checked = 0, worst = 0, brightest = 0;
  for (int y = 40; y < int(kHeight); y += 4)
    for (int x = 4; x < int(kWidth); x += 8) {
      const glm::vec2 ndc((x + 0.5f) / kWidth * 2 - 1, (y + 0.5f) / kHeight * 2 - 1);
      const glm::vec4 a = inv * glm::vec4(ndc, 1.0f, 1.0f), b = inv * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 o = glm::vec3(a) / a.w, d = glm::normalize(glm::vec3(b) / b.w - o);
      if (d.z >= -1e-3f) continue;
      const glm::vec3 w = o - (o.z / d.z) * d;  // on z = 0
      if (std::abs(w.x) > 4.5f || std::abs(w.y) > 4.5f) continue;
      const glm::vec3 n(0, 0, 1), h = glm::normalize(l + glm::normalize(p.camera.position - w));
      const float nl = glm::dot(n, l);
      const glm::vec3 want = e * nl / 3.14159265f + 0.3f * (20.0f + 8.0f) / (8.0f * 3.14159265f) *
                                                        std::pow(glm::dot(n, h), 20.0f) * e * nl;
      const glm::ivec3 got = rgb_at(image, {x, y});
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] - srgb8(want[c])));
      brightest = std::max(brightest, srgb8(want.x) - srgb8(e.x * nl / 3.14159265f));
      ++checked;
    }
  EXPECT_GT(checked, 30);
  EXPECT_GT(brightest, 40) << "the highlight is in the sampled pixels";
  EXPECT_LE(worst, 3);
}

// Two sources, [Ambrosj16] Algorithm 6 (no direct term): a ground point in the shadow of
// sources[0] only is lit by the OEM "env source 1 present, env source 0 removed" (index 0b10:
// bit j set = env source j present), and the other way round; both seen: the whole map.
TEST(EnvironmentShading, ShadowTestsPickTheOemSubset) {
  Gpu gpu;
  RenderPacket p;
  MeshDraw ground;
  ground.mesh = make_box({6.0f, 3.0f, 0.05f});
  ground.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.05f));
  p.meshes.push_back(ground);
  MeshDraw blocker;  // 1 x 1 x 0.5 m at 1.5 m: shadows at x in [-2.25, -0.75] and [0.75, 2.25]
  blocker.mesh = make_box({0.5f, 0.5f, 0.25f});
  blocker.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.5f));
  p.meshes.push_back(blocker);
  p.camera.position = {0.0f, -0.01f, 12.0f};  // straight down
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.7f;
  p.view.sky = false;
  p.view.lighting_only = true;
  p.view.tonemap = ViewSettings::Tonemap::kLinear;
  EnvironmentShading& e = p.environment;
  e.enabled = true;
  e.direct_diffuse = false;
  e.oem_source_count = 2;
  e.sources = {{{1, 0, 1}, glm::vec3(0.0f), 0, 1.0f}, {{-1, 0, 1}, glm::vec3(0.0f), 1, 1.0f}};
  // Index = env sources present: 0 none (black), 1 only 0 (red), 2 only 1 (green), 3 both (blue).
  e.oem_sh = constant_sets({glm::vec3(0.0f), {0.5f, 0, 0}, {0, 0.5f, 0}, {0, 0, 0.5f}});
  const ImageRgba8 image = gpu.render(p);
  const int on = srgb8(0.5f);
  auto expect = [&](glm::vec3 w, glm::ivec3 want, const char* what) {
    const glm::ivec3 got = rgb_at(image, pixel_of(p, w));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 2) << what << " channel " << c;
  };
  expect({-1.5f, 0.0f, 0.0f}, {0, on, 0}, "in the shadow of source 0 only");
  expect({1.5f, 0.0f, 0.0f}, {on, 0, 0}, "in the shadow of source 1 only");
  expect({4.0f, 1.0f, 0.0f}, {0, 0, on}, "seen by both");
  expect({0.0f, -2.0f, 0.0f}, {0, 0, on}, "seen by both (between the shadows)");
  // Switched off ([Ambrosj16] sec. 5.2.1): source 1 never lit -> the both-seen ground shows
  // OEM "only 0".
  e.sources[1].weight = 0.0f;
  const ImageRgba8 off = gpu.render(p);
  const glm::ivec3 got = rgb_at(off, pixel_of(p, {4.0f, 1.0f, 0.0f}));
  EXPECT_NEAR(got.r, on, 2);
  EXPECT_NEAR(got.b, 0, 2);
}

// The shader's SH basis is sh/basis.h's: a sphere lit by a random 3-band set (no sources seen:
// their irradiance is zero), compared pixel by pixel with the CPU evaluation.
TEST(EnvironmentShading, ShBasisMatchesTheLibrary) {
  Gpu gpu;
  RenderPacket p;
  MeshDraw ball;
  ball.mesh = test::make_uv_sphere(48, 96, 1.0f);
  p.meshes.push_back(ball);
  p.camera.position = {0.0f, -4.0f, 0.0f};
  p.camera.target = {0.0f, 0.0f, 0.0f};
  p.camera.vertical_fov = 0.7f;
  p.view.sky = false;
  p.view.lighting_only = true;
  p.view.tonemap = ViewSettings::Tonemap::kLinear;
  p.environment = one_source({0, 0, 1}, glm::vec3(0.0f));
  p.environment.rotation_z = 0.7f;
  sh::CoeffsRgb<3> f{};
  const float values[9] = {1.2f, 0.3f, -0.25f, 0.2f, 0.15f, -0.1f, 0.12f, 0.08f, -0.14f};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 9; ++i) f[c][i] = values[i] * (1.0f - 0.2f * c);
  auto sets = std::make_shared<std::vector<float>>();
  for (int set = 0; set < 2; ++set)
    for (int c = 0; c < 3; ++c) sets->insert(sets->end(), f[c].begin(), f[c].end());
  p.environment.oem_sh = sets;
  const ImageRgba8 image = gpu.render(p);
  const glm::mat4 inv = glm::inverse(view_projection(p.camera, float(kWidth) / float(kHeight)));
  const float band[9] = {1, 2.f / 3, 2.f / 3, 2.f / 3, .25f, .25f, .25f, .25f, .25f};
  int checked = 0, worst = 0;
  for (int y = 4; y < int(kHeight); y += 6)
    for (int x = 4; x < int(kWidth); x += 6) {
      const glm::vec2 ndc((x + 0.5f) / kWidth * 2 - 1, (y + 0.5f) / kHeight * 2 - 1);
      glm::vec4 a = inv * glm::vec4(ndc, 1.0f, 1.0f), b = inv * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 o = glm::vec3(a) / a.w, d = glm::normalize(glm::vec3(b) / b.w - o);
      const float t_mid = -glm::dot(o, d), miss = glm::dot(o, o) - t_mid * t_mid;
      if (miss > 0.9f * 0.9f) continue;  // off the sphere or near its rim (facets)
      const glm::vec3 n = glm::normalize(o + (t_mid - std::sqrt(1.0f - miss)) * d);
      const float r = p.environment.rotation_z;
      const glm::vec3 m(std::cos(r) * n.x + std::sin(r) * n.y,
                        -std::sin(r) * n.x + std::cos(r) * n.y, n.z);
      const auto yb = sh::eval_basis<3>(m);
      const glm::ivec3 got = rgb_at(image, {x, y});
      for (int c = 0; c < 3; ++c) {
        float e = 0;
        for (int i = 0; i < 9; ++i) e += band[i] * f[c][i] * yb[i];
        worst = std::max(worst, std::abs(got[c] - srgb8(std::max(e, 0.0f))));
      }
      ++checked;
    }
  EXPECT_GT(checked, 40);
  EXPECT_LE(worst, 4);  // the mesh's facets and 16-bit HDR
}

// The maps are drawn again only when the sources or the meshes change; a frame that reuses
// them draws the same image.
TEST(EnvironmentShading, MapsRedrawnOnlyWhenTheSceneChanges) {
  Gpu gpu;
  RenderPacket p = ground_scene(true);
  p.environment = one_source({0.3f, 0.2f, 0.9f}, glm::vec3(2.0f));
  const ImageRgba8 first = gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 1u);
  EXPECT_EQ(differing_pixels(gpu.render(p), first), 0u);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 1u) << "nothing changed";
  p.environment.sources[0].weight = 0.5f;  // not in the maps
  gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 1u);
  p.meshes[1].transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.0f, 1.0f));
  const ImageRgba8 moved = gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 2u) << "a mesh moved";
  EXPECT_NE(differing_pixels(moved, first), 0u);
  p.environment.sources[0].direction = {0.3f, 0.25f, 0.9f};
  gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 3u) << "the source moved";
  p.environment.shadow_map_size = 256;
  gpu.render(p);
  EXPECT_EQ(gpu.renderer.stats().shadow_renders, 4u) << "new maps";
}

// Bad input: no sources, no meshes, a bad packet: drawn exactly as without the shading; a
// source at the zenith or on the horizon draws (finite box).
TEST(EnvironmentShading, BadInputFallsBackToTodaysPath) {
  PENUMBRA_STABILITY("no sources, no meshes, a bad packet; a source at the zenith or horizon",
                     "drawn exactly as without the shading; the error is stated; finite box", "-");
  Gpu gpu;
  const RenderPacket plain = test::mesh_scene();
  const ImageRgba8 today = gpu.render(plain);
  RenderPacket none = plain;
  none.environment.enabled = true;  // zero sources
  EXPECT_EQ(differing_pixels(gpu.render(none), today), 0u);
  EXPECT_EQ(gpu.renderer.stats().shadow_maps, 0u);
  RenderPacket bad = plain;
  bad.environment = one_source({0, 0, 1}, glm::vec3(1.0f));
  bad.environment.oem_sh = std::make_shared<std::vector<float>>(3, 0.0f);
  EXPECT_EQ(differing_pixels(gpu.render(bad), today), 0u);
  EXPECT_EQ(gpu.renderer.stats().shadow_maps, 0u);
  EXPECT_EQ(gpu.renderer.stats().environment_error,
            "environment.oem_sh: 3 floats, expected 54 (2^1 sets x 27)");
  RenderPacket empty = test::environment_scene();  // no meshes
  const ImageRgba8 sky = gpu.render(empty);
  empty.environment = one_source({0, 0, 1}, glm::vec3(1.0f));
  EXPECT_EQ(differing_pixels(gpu.render(empty), sky), 0u);
  EXPECT_EQ(gpu.renderer.stats().shadow_maps, 0u);
  EXPECT_EQ(gpu.renderer.stats().environment_error, "");
  for (glm::vec3 d : {glm::vec3(0, 0, 1), glm::vec3(1, 0, 0), glm::vec3(0, -1, 1e-6f)}) {
    RenderPacket p = ground_scene(true);
    p.environment = one_source(d, glm::vec3(2.0f));
    const ImageRgba8 image = gpu.render(p);
    EXPECT_EQ(gpu.renderer.stats().shadow_maps, 1u);
    EXPECT_NE(differing_pixels(image, gpu.render(ground_scene(true))), 0u);
  }
}

}  // namespace
}  // namespace penumbra::render
