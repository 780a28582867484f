// Sky pass: a full-screen triangle at the far plane (depth 0 with reversed depth), drawn after
// the opaque passes with depth test GREATER_OR_EQUAL and no depth write, so it only shades
// pixels no geometry covered. Radiance from the equirectangular environment map (row 0 =
// zenith, u = azimuth from +x towards +y; penumbra/sh/projection.h): variant 1, or the
// procedural sky: variant 0.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

#ifdef PENUMBRA_VERTEX
// The view ray, from the eye to the near plane: affine across the screen, so it is computed per
// vertex and interpolated (normalised per pixel).
layout(location = 0) noperspective out vec3 v_ray;
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);  // (0,0), (2,0), (0,2)
  vec2 ndc = p * 2.0 - 1.0;
  vec4 near = camera.inv_view_proj * vec4(ndc, 1.0, 1.0);  // depth 1 = near plane
  v_ray = near.xyz / near.w - camera.position.xyz;
  gl_Position = vec4(ndc, 0.0, 1.0);
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(set = 0, binding = 1) uniform sampler2D environment;
layout(location = 0) noperspective in vec3 v_ray;
layout(location = 0) out vec4 out_color;
const float kPi = 3.14159265358979;

// atan(y, x) to within 1e-5 rad (a minimax polynomial on [0, 1] and the octant symmetries) and
// acos(x) to within 7e-5 rad (Abramowitz and Stegun 4.4.45): 0.002 and 0.02 texel of a
// 2048 x 1024 map, and cheaper on lavapipe than GLSL's atan and acos (docs/play.md).
float fast_atan2(float y, float x) {
  float ax = abs(x), ay = abs(y);
  float a = min(ax, ay) / max(max(ax, ay), 1e-30);
  float s = a * a;
  float r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  r = ay > ax ? 0.5 * kPi - r : r;
  r = x < 0.0 ? kPi - r : r;
  return y < 0.0 ? -r : r;
}
float fast_acos(float x) {
  float ax = min(abs(x), 1.0);
  float r = sqrt(1.0 - ax) * (((-0.0187293 * ax + 0.0742610) * ax - 0.2121144) * ax + 1.5707288);
  return x < 0.0 ? kPi - r : r;
}

void main() {
  vec3 dir = normalize(v_ray);
  vec3 c;
  if (kVariant == 1) {
    float u = (fast_atan2(dir.y, dir.x) - camera.params.w) / (2.0 * kPi);
    u -= floor(u);
    float v = fast_acos(dir.z) / kPi;
    c = textureLod(environment, vec2(u, v), 0.0).rgb * camera.params.z;
  } else {
    c = procedural_sky(dir, true);
  }
  out_color = vec4(c, 1.0);
}
#endif
