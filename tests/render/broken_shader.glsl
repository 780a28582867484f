// Deliberately broken shader for the shader-error test (tests/render/CMakeLists.txt): the build's
// compile step must name this file and line 8.
#version 460
layout(location = 0) out vec4 out_color;
#ifdef PENUMBRA_FRAGMENT
void main() {
  vec3 c = vec3(1.0);
  out_color = vec4(c, undefined_variable);
}
#endif
