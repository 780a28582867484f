// Debug primitives pass: lines and points (one vertex = position + colour) and, compiled with
// DEBUG_SPHERES, instanced wire spheres (a unit wire sphere per vertex; centre, radius and
// colour per instance). Unlit HDR colours, depth tested.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

#ifdef PENUMBRA_VERTEX
#ifdef DEBUG_SPHERES
layout(location = 0) in vec3 in_unit;
layout(location = 1) in vec3 in_center;
layout(location = 2) in float in_radius;
layout(location = 3) in vec3 in_color;
#else
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_color;
#endif
layout(location = 0) out vec3 v_color;
void main() {
#ifdef DEBUG_SPHERES
  vec3 p = in_center + in_radius * in_unit;
#else
  vec3 p = in_position;
#endif
  v_color = in_color;
  gl_PointSize = camera.params.y;
  gl_Position = camera.view_proj * vec4(p, 1.0);
}
#endif

#ifdef PENUMBRA_FRAGMENT
layout(location = 0) in vec3 v_color;
layout(location = 0) out vec4 out_color;
void main() { out_color = vec4(v_color, 1.0); }
#endif
