// Terrain pass: the height field as a triangle mesh at a level of detail (see
// engine/render/include/penumbra/render/terrain_pass.h). Vertices come from gl_VertexIndex and
// the heights storage buffer (no vertex buffer): index i is sample i (y * width + x). The
// fragment shader samples the per-texel lighting texture (texel centres on the height samples),
// so lighting keeps its full resolution at any geometric detail, and multiplies the albedo.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(push_constant) uniform Push {
  vec4 origin_cell;  // xyz: world position of sample (0, 0) at height 0; w: cell size
  vec4 albedo;       // rgb: albedo as shown (1 in the lighting-only view)
  vec4 lighting_size;  // xy: texels of the lighting texture (1x1: none), z: RGBM decode scale
  ivec4 grid;        // x, y: samples along x and y
} pc;

#ifdef PENUMBRA_VERTEX
layout(set = 0, binding = 1, std430) readonly buffer Heights { float heights[]; };
layout(location = 0) out vec2 v_uv;

// a / b for 0 <= a < 2^22, b > 0, in float: exact there (the error of the quotient, at most
// 2^-22 relative, stays below the 0.5 / b margin), and cheaper than integer division, which
// llvmpipe cannot vectorise (one scalar divide per lane).
int quotient(int a, int b) { return int((float(a) + 0.5) / float(b)); }

void main() {
  int w = pc.grid.x;
  int i = gl_VertexIndex;
  int y = quotient(i, w);
  int x = i - y * w;
  vec3 p = pc.origin_cell.xyz + vec3(x * pc.origin_cell.w, y * pc.origin_cell.w, heights[i]);
  // Texel centres on the samples: (x + 0.5) / size for a lighting texture of the grid's size; in
  // general x / (grid - 1) of the way between the first and the last texel centre. Done per
  // vertex: the fragment shader only samples (on lavapipe every fragment counts).
  v_uv = (vec2(x, y) / vec2(pc.grid.xy - 1) * (pc.lighting_size.xy - 1.0) + 0.5) /
         pc.lighting_size.xy;
  gl_Position = camera.view_proj * vec4(p, 1.0);
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(set = 0, binding = 2) uniform sampler2D lighting;
layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;
void main() {
  // albedo.rgb is already view_albedo's (the renderer applies the lighting-only toggle), and the
  // 1x1 placeholder texture (lighting 1) is bound when there is no lighting.
  // RGBM (engine/render/include/penumbra/render/lighting_texels.h); the placeholder is 1, scale 1.
  vec4 t = texture(lighting, v_uv);
  out_color = vec4(pc.albedo.rgb * (t.rgb * (t.a * pc.lighting_size.z)), 1.0);
}
#endif
