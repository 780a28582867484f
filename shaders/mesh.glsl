// Mesh pass: triangle meshes with a model matrix and, when supplied, per-vertex lighting
// (linear RGB from the lighting systems) multiplied by the albedo: variant 1. Without lighting
// (variant 0), a fixed sun + sky preview shading (normals from the mesh, or flat from screen
// derivatives). With MESH_ENVIRONMENT: the environment shading (packet.h EnvironmentShading,
// shadow_pass.h), [Ambrosj16] Algorithms 5-6 with a direct term and the Blinn term's radiance.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(push_constant) uniform Push {
  mat4 model;
  vec4 albedo;    // rgb: albedo
  vec4 specular;  // rgb: Blinn reflectance (0: none), a: exponent (MESH_ENVIRONMENT only)
} pc;

#ifdef MESH_ENVIRONMENT
// Mirrors EnvironmentBlock in engine/render/src/shadow_pass.cpp (std140).
layout(set = 0, binding = 1, std140) uniform EnvironmentBlock {
  mat4 shadow_view_proj[3];   // world -> the source's shadow clip space (x, y in [-1, 1], z in [0, 1])
  vec4 source_direction[3];   // xyz: towards the source (unit), w: weight (0 off ... 1 on)
  vec4 source_irradiance[3];  // rgb: irradiance at normal incidence
  vec4 params;                // x: source count, y: direct diffuse (1/0), z, w: cos, sin of the map's rotation
  vec4 sets[8 * 9];           // set V (bit k: source k seen) x 9 coefficients: radiance per unit albedo
} env;
layout(set = 0, binding = 2) uniform sampler2D shadow_maps[3];

// 3-band real SH (sh/basis.h: index l(l+1)+m, no Condon-Shortley phase, band 1 as y, z, x).
void sh_basis(vec3 d, out float y[9]) {
  y[0] = 0.282094792;
  y[1] = 0.488602512 * d.y;
  y[2] = 0.488602512 * d.z;
  y[3] = 0.488602512 * d.x;
  y[4] = 1.092548431 * d.x * d.y;
  y[5] = 1.092548431 * d.y * d.z;
  y[6] = 0.315391565 * (3.0 * d.z * d.z - 1.0);
  y[7] = 1.092548431 * d.x * d.z;
  y[8] = 0.546274215 * (d.x * d.x - d.y * d.y);
}

// Source k's shadow-map test ([Ambrosj16] sec. 3.6): lit unless the stored depth is nearer the
// source than this point minus the slope-scaled bias max(0.05 (1 - n.l), 0.005) (in the
// map's [0, 1] depth). Outside the map: lit.
// s: the point in the map's clip space (orthographic, so interpolated from the vertices as
// [Ambrosj16] Algorithm 5 does).
bool seen(int k, vec3 s, float n_dot_l) {
  vec2 uv = 0.5 * s.xy + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || s.z > 1.0) return true;
  float bias = max(0.05 * (1.0 - n_dot_l), 0.005);
  return s.z - bias <= texture(shadow_maps[k], uv).r;
}
#endif

#ifdef PENUMBRA_VERTEX
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#ifndef MESH_ENVIRONMENT
layout(location = 2) in vec3 in_lighting;
#endif
layout(location = 0) out vec3 v_lighting;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_world;
#ifdef MESH_ENVIRONMENT
layout(location = 3) out vec3 v_shadow[3];  // the point in each source's shadow clip space
#endif
void main() {
  vec4 world = pc.model * vec4(in_position, 1.0);
  v_world = world.xyz;
  v_normal = mat3(pc.model) * in_normal;
#ifdef MESH_ENVIRONMENT
  v_lighting = vec3(0.0);
  for (int k = 0; k < 3; ++k) v_shadow[k] = (env.shadow_view_proj[k] * world).xyz;
#else
  v_lighting = in_lighting;
#endif
  gl_Position = camera.view_proj * world;
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(location = 0) in vec3 v_lighting;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_world;
#ifdef MESH_ENVIRONMENT
layout(location = 3) in vec3 v_shadow[3];
#endif
layout(location = 0) out vec4 out_color;
void main() {
#ifdef MESH_ENVIRONMENT
  vec3 n = v_normal;
  vec3 to_eye = normalize(camera.position.xyz - v_world);
  if (dot(n, n) < 1e-12) {  // no normals: the flat one, turned towards the eye
    n = cross(dFdx(v_world), dFdy(v_world));
    if (dot(n, to_eye) < 0.0) n = -n;
  }
  n = normalize(n);  // the mesh's own normals are kept (front faces only are drawn)
  // Pipeline variant (mesh_pass.cpp): bits 0-1 the source count, bit 2 the direct diffuse,
  // so the loop and the set index are constants (lavapipe runs every lane of a branch).
  const int count = kVariant & 3;
  const bool direct = (kVariant & 4) != 0;
  int visible = 0;
  vec3 diffuse = vec3(0.0), glossy = vec3(0.0);
  float exponent = pc.specular.a;
  for (int k = 0; k < count; ++k) {
    vec3 l = env.source_direction[k].xyz;
    float w = env.source_direction[k].w;
    float n_dot_l = dot(n, l);
    if (w <= 0.0 || !seen(k, v_shadow[k], n_dot_l)) continue;
    visible |= 1 << k;
    vec3 e = w * env.source_irradiance[k].rgb * max(n_dot_l, 0.0);
    if (direct) diffuse += e * 0.318309886;  // E / pi: radiance per unit albedo
    if (exponent > 0.0) {
      vec3 h = normalize(l + to_eye);
      glossy += e * (exponent + 8.0) * 0.0397887358 * pow(max(dot(n, h), 0.0), exponent);
    }
  }
  // The OEM set for the visibility mask, evaluated in the map's frame (R_z(-rotation) n).
  vec3 m = vec3(env.params.z * n.x + env.params.w * n.y, -env.params.w * n.x + env.params.z * n.y,
                n.z);
  float y[9];
  sh_basis(m, y);
  int base = (direct ? 0 : visible) * 9;
  vec3 ambient = vec3(0.0);
  for (int i = 0; i < 9; ++i) ambient += env.sets[base + i].rgb * y[i];
  diffuse += max(ambient, vec3(0.0));
  out_color = vec4(view_albedo(pc.albedo.rgb) * diffuse + pc.specular.rgb * glossy, 1.0);
#else
  vec3 light;
  if (kVariant == 1) {
    light = v_lighting;
  } else {
    vec3 n = v_normal;
    if (dot(n, n) < 1e-12) n = cross(dFdx(v_world), dFdy(v_world));
    n = normalize(n);
    if (dot(n, camera.position.xyz - v_world) < 0.0) n = -n;
    float sun = max(dot(n, camera.sun_direction.xyz), 0.0);
    light = 0.05 * camera.sun_radiance.rgb * sun + procedural_sky(n, false);
  }
  out_color = vec4(view_albedo(pc.albedo.rgb) * light, 1.0);
#endif
}
#endif
