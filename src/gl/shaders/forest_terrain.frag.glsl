// forest_terrain.frag.glsl — the terrain's colour (lighting baked in), fogged;
// wireframe: flat green.
#version 450 core
#include "fog.glsl"
in vec3 v_world;
in vec2 v_uv;
uniform sampler2D u_colour;
uniform int u_flat;
out vec4 o_colour;
void main() {
  if (u_flat != 0) { o_colour = vec4(0.08, 0.2, 0.08, 1.0); return; }
  vec3 c = texture(u_colour, v_uv).rgb;
  o_colour = vec4(fogged(c, v_world), 1.0);
}
