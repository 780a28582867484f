// The render packet: everything the renderer draws in one frame, as plain data.
//
// Contract: the renderer reads a RenderPacket and nothing else (never ECS storage); the extract
// system (systems/render_extract) fills one per frame. Large arrays (height fields, lighting
// textures, meshes, vertex lighting, environment maps) are shared through shared_ptr<const>:
// the producer never changes data behind a published pointer, it publishes a new one. The
// renderer keeps the pointers it uploaded and uploads again only when a pointer changes, so a
// frame that changes nothing uploads nothing (vertex lighting and debug primitives, which are
// per-frame data, are copied every frame).
//
// Conventions: world space in metres, right-handed, z up. Colours are linear RGB; lighting and
// sky values are radiance-like HDR values (any scale; ViewSettings::exposure_ev brings them to
// display range before the filmic tonemap).
//
// Threading: built by one thread, then read by the render thread; it must not change while
// Renderer::render reads it. The shared arrays may be read by both at once (they are const).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"

namespace penumbra::render {

struct CameraView {
  glm::vec3 position{0.0f, -10.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
  float vertical_fov = 1.0f;  // radians
  float near_plane = 0.1f;    // metres, > 0
  float far_plane = 2000.0f;  // metres, > near_plane
};

struct TerrainDraw {
  std::shared_ptr<const data::HeightField> heights;  // null or < 2x2 samples: no terrain
  glm::vec3 origin{0.0f};                            // world position of sample (0, 0) at height 0
  glm::vec3 albedo{0.5f};                            // the shaded colour is albedo * lighting
  // Per-texel lighting: lighting_width * lighting_height linear RGB values, row-major (row =
  // y). Texel (i, j) is centred on the terrain point at fraction (i / (lighting_width - 1),
  // j / (lighting_height - 1)) of its extent, so a texture the size of the height field puts
  // one texel on each height sample. Null (or too small for its size): lighting 1.
  std::shared_ptr<const std::vector<glm::vec3>> lighting;
  int lighting_width = 0;
  int lighting_height = 0;
};

struct MeshDraw {
  std::shared_ptr<const data::MeshData> mesh;  // positions, normals (optional), indices
  glm::mat4 transform{1.0f};                   // object -> world
  glm::vec3 albedo{1.0f};                      // linear; the shaded colour is albedo * lighting
  // Per-vertex lighting, one linear RGB value per mesh position. Null: the mesh pass shades with
  // a fixed sun and sky from Sky (a preview, not the lighting systems' result).
  std::shared_ptr<const std::vector<glm::vec3>> vertex_lighting;
  // Glossy reflection, used only by the environment shading (EnvironmentShading): a normalised
  // Blinn lobe (exponent + 8) / (8 pi) (n.h)^exponent of this reflectance per visible source;
  // exponent 0: none (Lambertian).
  glm::vec3 specular{0.04f};
  float specular_exponent = 0.0f;
};

// A light source of the environment map drawn as a directional light with a shadow map
// ([Ambrosj16] sec. 3.6, 4.3).
struct ShadowedSource {
  glm::vec3 direction{0.0f, 0.0f, 1.0f};  // world, from the scene towards the source
  glm::vec3 irradiance{0.0f};             // RGB irradiance at normal incidence
  std::uint32_t oem_bit = 0;  // the source's bit in the index of EnvironmentShading::oem_sh
  float weight = 1.0f;        // light switching ([Ambrosj16] sec. 5.2.1): 0 off ... 1 on
};

// Opt-in per-pixel environment lighting of the meshes ([Ambrosj16] ch. 4, Algorithm 6): one
// shadow map per source, and per fragment the occluded environment map (OEM) chosen by the
// shadow-map tests. When enabled with at least one source, every mesh is shaded from this
// (its vertex_lighting is not used); otherwise the mesh pass is today's (vertex lighting or
// preview). Used by the mesh pass only (the terrain has its own key light per texel).
//
// Per fragment, with V the sources it sees (shadow-map tests, bit k: sources[k]):
//   direct_diffuse = false ([Ambrosj16] Algorithm 6): diffuse from the OEM with the sources in
//     V present and the other shadowed sources removed; no direct term;
//   direct_diffuse = true (default): diffuse from the OEM with every shadowed source removed
//     plus, per source in V, irradiance * max(0, n.l) (exact cosine, no SH ringing);
// and in both, per source in V, the Blinn term of MeshDraw::specular with its irradiance.
// A weight below 1 blends the source linearly towards "off" (never lit, removed from the OEM).
struct EnvironmentShading {
  static constexpr std::size_t kMaxSources = 3;  // sources past the third are ignored
  bool enabled = false;
  bool direct_diffuse = true;
  std::vector<ShadowedSource> sources;
  // The OEM sets: 2^n sets x 3 channels (r, g, b) x 9 coefficients, the 3-band SH (sh/basis.h
  // order) of the map's radiance in the map's frame, set i holding the sources whose bit is set
  // in i (components::EnvironmentLight::oem_sh3). n: the bit count (every oem_bit < n).
  std::shared_ptr<const std::vector<float>> oem_sh;
  std::uint32_t oem_source_count = 0;
  // Bits of the sources kept in every fragment's OEM (detected but without a shadow map).
  std::uint32_t present_mask = 0;
  float rotation_z = 0.0f;  // radians about +z, the map's (like Sky::environment_rotation)
  std::uint32_t shadow_map_size = 1024;  // texels per side, clamped to [64, 4096]
  // Which environment these sets were made from (render_extract re-packs only on a change).
  std::uint64_t version = 0;
};

// Debug primitives, drawn unlit with depth test (HDR colours, tonemapped like the scene).
struct SphereDraw {  // a wire sphere (three great circles plus latitude rings)
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{1.0f};
};
struct LineDraw {
  glm::vec3 a{0.0f}, b{0.0f};
  glm::vec3 color{1.0f};
};
struct PointDraw {
  glm::vec3 position{0.0f};
  glm::vec3 color{1.0f};
};

struct Sky {
  // Equirectangular map (row 0 = zenith, azimuth from +x towards +y: sh/projection.h); null:
  // a procedural sky from the colours below.
  std::shared_ptr<const data::EnvironmentMap> environment;
  float environment_intensity = 1.0f;
  // Radians counter-clockwise about +z: world radiance L(R_z(rotation) w) = map(w), as
  // components::EnvironmentLight and reference::EnvironmentLight.
  float environment_rotation = 0.0f;
  glm::vec3 sun_direction{0.4f, 0.3f, 0.866f};  // towards the sun; normalised by the renderer
  glm::vec3 sun_radiance{40.0f, 36.0f, 30.0f};  // the sun disc (procedural sky)
  glm::vec3 zenith{0.25f, 0.45f, 0.9f};
  glm::vec3 horizon{0.8f, 0.85f, 0.9f};
  glm::vec3 ground{0.25f, 0.22f, 0.2f};
};

// How to show the frame: exposure, tonemap and the debug-view toggles (the ImGui overlay edits
// these).
struct ViewSettings {
  enum class Tonemap : std::uint32_t { kFilmic = 0, kLinear = 1 };
  float exposure_ev = 0.0f;  // radiance is scaled by 2^exposure_ev before the tonemap
  Tonemap tonemap = Tonemap::kFilmic;
  bool sky = true;
  bool terrain = true;
  bool meshes = true;
  bool debug = true;
  bool lighting_only = false;  // albedo 1: show the lighting the systems computed
  float point_size = 2.0f;     // pixels (1 where the device lacks large points)
  // Terrain level of detail: the largest vertical error, in pixels on screen, a coarser
  // triangle may show (render/terrain_bintree.h); 0: full detail. 3: the lighting is a
  // per-pixel texture, so only the shape moves (why 3 and what it costs: docs/play.md).
  float terrain_lod_pixels = 3.0f;
};

struct RenderPacket {
  CameraView camera;
  Sky sky;
  TerrainDraw terrain;
  std::vector<MeshDraw> meshes;
  std::vector<SphereDraw> spheres;
  std::vector<LineDraw> lines;
  std::vector<PointDraw> points;
  ViewSettings view;
  EnvironmentShading environment;

  // Empties the per-frame lists, keeping their capacity (camera, sky, terrain, view stay).
  void clear_lists() {
    meshes.clear();
    spheres.clear();
    lines.clear();
    points.clear();
  }
};

}  // namespace penumbra::render
