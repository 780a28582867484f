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
void main() {
  vec3 dir = normalize(v_ray);
  vec3 c;
  if (kVariant == 1) {
    float u = (atan(dir.y, dir.x) - camera.params.w) / (2.0 * kPi);
    u -= floor(u);
    float v = acos(clamp(dir.z, -1.0, 1.0)) / kPi;
    c = textureLod(environment, vec2(u, v), 0.0).rgb * camera.params.z;
  } else {
    c = procedural_sky(dir, true);
  }
  out_color = vec4(c, 1.0);
}
#endif
