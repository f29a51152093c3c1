// forest_sky.frag.glsl — the sky: the view ray's direction into the sky cube,
// or without one a gradient from the fog's colour at the horizon to blue.
#version 450 core
in vec2 v_ndc;
uniform mat4 u_inverse;
uniform vec3 u_fog_colour;
uniform int u_has_cube;
uniform samplerCube u_cube;
out vec4 o_colour;
void main() {
  vec4 a = u_inverse * vec4(v_ndc, -1.0, 1.0), b = u_inverse * vec4(v_ndc, 1.0, 1.0);
  vec3 d = normalize(b.xyz / b.w - a.xyz / a.w);
  if (u_has_cube != 0) { o_colour = vec4(texture(u_cube, d).rgb, 1.0); return; }
  vec3 zenith = vec3(0.30, 0.50, 0.82);
  float t = clamp(d.y * 2.2, 0.0, 1.0);
  o_colour = vec4(mix(u_fog_colour, zenith, sqrt(t)), 1.0);
}
