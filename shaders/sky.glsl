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
layout(location = 0) out vec3 v_ray;
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
layout(location = 0) in vec3 v_ray;
layout(location = 0) out vec4 out_color;
const float kPi = 3.14159265358979;

// atan(y, x) in [-pi, pi] to within 1.2e-5 rad (Abramowitz & Stegun 4.4.47 on [0, 1] and the
// octant symmetries), under a tenth of an environment-map texel at 4096 texels around; cheaper
// on lavapipe than the exact atan and acos.
float fast_atan2(float y, float x) {
  float ax = abs(x), ay = abs(y);
  float a = min(ax, ay) / max(max(ax, ay), 1e-30);
  float s = a * a;
  float r =
      a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))));
  if (ay > ax) r = 0.5 * kPi - r;
  if (x < 0.0) r = kPi - r;
  return y < 0.0 ? -r : r;
}

void main() {
  vec3 dir = normalize(v_ray);
  vec3 c;
  if (kVariant == 1) {
    float u = (fast_atan2(dir.y, dir.x) - camera.params.w) / (2.0 * kPi);
    u -= floor(u);
    float v = fast_atan2(length(dir.xy), dir.z) / kPi;  // acos(dir.z) / pi
    c = textureLod(environment, vec2(u, v), 0.0).rgb * camera.params.z;
  } else {
    c = procedural_sky(dir, true);
  }
  out_color = vec4(c, 1.0);
}
#endif
