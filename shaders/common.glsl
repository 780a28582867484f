// Shared by the 3D passes (sky, terrain, mesh, debug): the per-frame camera block, bound as
// push-descriptor binding 0 of set 0, and the procedural sky. Layout mirrors CameraBlock in
// engine/render/src/renderer.cpp (std140).
layout(set = 0, binding = 0, std140) uniform CameraBlock {
  mat4 view_proj;
  mat4 inv_view_proj;
  vec4 position;       // xyz: eye
  vec4 sun_direction;  // xyz: towards the sun, normalised
  vec4 sun_radiance;   // rgb
  vec4 sky_zenith;     // rgb
  vec4 sky_horizon;    // rgb
  vec4 sky_ground;     // rgb
  vec4 params;  // x: lighting-only view (1/0), y: point size, z: environment intensity, w: its rotation
} camera;

// Pipeline variant (PipelineDesc::variant): lets a pass pick a code path at pipeline creation.
layout(constant_id = 0) const int kVariant = 0;

vec3 view_albedo(vec3 albedo) { return camera.params.x > 0.5 ? vec3(1.0) : albedo; }

// Procedural sky radiance towards direction d (unit): a zenith-horizon-ground gradient and,
// with_sun, a sun disc of about 1.5 degrees.
vec3 procedural_sky(vec3 d, bool with_sun) {
  vec3 c;
  if (d.z >= 0.0) {
    c = mix(camera.sky_horizon.rgb, camera.sky_zenith.rgb, sqrt(d.z));
  } else {
    c = mix(camera.sky_horizon.rgb, camera.sky_ground.rgb, sqrt(sqrt(-d.z)));
  }
  if (with_sun) {
    float s = dot(d, camera.sun_direction.xyz);
    c += camera.sun_radiance.rgb * smoothstep(0.99955, 0.99970, s);
  }
  return c;
}
