// Mesh pass: triangle meshes with a model matrix and, when supplied, per-vertex lighting
// (linear RGB from the lighting systems) multiplied by the albedo: variant 1. Without lighting
// (variant 0), a fixed sun + sky preview shading (normals from the mesh, or flat from screen
// derivatives).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(push_constant) uniform Push {
  mat4 model;
  vec4 albedo;  // rgb: albedo
} pc;

#ifdef PENUMBRA_VERTEX
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_lighting;
layout(location = 0) out vec3 v_lighting;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_world;
void main() {
  vec4 world = pc.model * vec4(in_position, 1.0);
  v_world = world.xyz;
  v_normal = mat3(pc.model) * in_normal;
  v_lighting = in_lighting;
  gl_Position = camera.view_proj * world;
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(location = 0) in vec3 v_lighting;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_world;
layout(location = 0) out vec4 out_color;
void main() {
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
}
#endif
