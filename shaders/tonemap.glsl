// Tonemap pass: HDR radiance * exposure -> display values in the 8-bit LDR image that is shown
// and saved as PNG. Filmic: the Hejl / Burgess-Dawson curve, whose output is already display
// encoded (it folds in a ~1/2.2 gamma), so the full-screen pass needs no pow() per channel (on
// lavapipe the exact sRGB encoding costs about as much as the rest of the pass). Linear: a clamp
// and the exact sRGB encoding (for inspecting values).
#version 460

layout(push_constant) uniform Push {
  vec4 params;  // x: exposure scale (2^EV), y: 0 filmic, 1 linear clamp
} pc;

#ifdef PENUMBRA_VERTEX
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(set = 0, binding = 0) uniform sampler2D hdr;
layout(location = 0) out vec4 out_color;

vec3 filmic_display(vec3 x) {
  x = max(x - 0.004, vec3(0.0));
  return (x * (6.2 * x + 0.5)) / (x * (6.2 * x + 1.7) + 0.06);
}
vec3 srgb_encode(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
  vec3 c = max(texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb, vec3(0.0)) * pc.params.x;
  c = pc.params.y > 0.5 ? srgb_encode(clamp(c, 0.0, 1.0)) : filmic_display(c);
  out_color = vec4(c, 1.0);
}
#endif
