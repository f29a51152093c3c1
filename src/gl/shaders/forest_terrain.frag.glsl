// forest_terrain.frag.glsl — the terrain's colour (with the objects' soft
// shadows), lit by the sun from the heights' normal, fogged; wireframe:
// flat green.
#version 450 core
#include "fog.glsl"
in vec3 v_world;
in vec2 v_uv;
uniform sampler2D u_colour;
uniform sampler2D u_height;
uniform float u_spacing;
uniform float u_squares;
uniform vec3 u_light;  // towards the sun
uniform float u_ambient;
uniform int u_flat;
out vec4 o_colour;
float height_at(vec2 sq) {
  return texture(u_height, (sq + 0.5) / (u_squares + 1.0)).r;
}
void main() {
  if (u_flat != 0) { o_colour = vec4(0.08, 0.2, 0.08, 1.0); return; }
  vec2 sq = v_world.xz / u_spacing;
  float dx = (height_at(sq + vec2(1.0, 0.0)) - height_at(sq - vec2(1.0, 0.0))) / (2.0 * u_spacing);
  float dz = (height_at(sq + vec2(0.0, 1.0)) - height_at(sq - vec2(0.0, 1.0))) / (2.0 * u_spacing);
  vec3 n = normalize(vec3(-dx, 1.0, -dz));
  vec3 c = texture(u_colour, v_uv).rgb;
  c *= (u_ambient + max(dot(n, u_light), 0.0)) / (u_ambient + 1.0);
  o_colour = vec4(fogged(c, v_world), 1.0);
}
