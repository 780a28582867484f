// Shadow pass: depth only, from an environment light source's orthographic box
// ([Ambrosj16] Algorithms 3-4; engine/render/include/penumbra/render/shadow_pass.h). The
// pipeline culls front faces (sec. 3.6), so the map holds the back faces' depth.
#version 460

layout(push_constant) uniform Push {
  mat4 mvp;  // the source's view_proj x model
} pc;

#ifdef PENUMBRA_VERTEX
layout(location = 0) in vec3 in_position;
void main() { gl_Position = pc.mvp * vec4(in_position, 1.0); }
#endif

#ifdef PENUMBRA_FRAGMENT
void main() {}
#endif
