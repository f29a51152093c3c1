// forest_terrain.vert.glsl — the terrain's CDLOD nodes (src/forest/terrain.c):
// per node one instance of the leaf grid, heights read from the height
// texture, the grid's odd vertices morphed onto the coarser grid between
// the level's morph start and its range, so that levels meet without cracks.
#version 450 core
layout(location = 0) in vec2 a_grid;
layout(location = 1) in vec4 a_node;  // origin x, z (squares), step, level
uniform mat4 u_viewproj;
uniform vec3 u_eye;
uniform float u_spacing;
uniform float u_squares;
uniform vec2 u_morph[24];
uniform sampler2D u_height;
out vec3 v_world;
out vec2 v_uv;
float height_at(vec2 sq) {
  return texture(u_height, (sq + 0.5) / (u_squares + 1.0)).r;
}
void main() {
  vec2 sq = a_node.xy + a_grid * a_node.z;
  vec3 p = vec3(sq.x * u_spacing, height_at(sq), sq.y * u_spacing);
  vec2 m = u_morph[int(a_node.w)];
  float k = clamp((distance(p, u_eye) - m.x) / max(m.y - m.x, 1e-6), 0.0, 1.0);
  vec2 g = a_grid - fract(a_grid * 0.5) * 2.0 * k;
  sq = a_node.xy + g * a_node.z;
  p = vec3(sq.x * u_spacing, height_at(sq), sq.y * u_spacing);
  v_world = p;
  v_uv = sq / u_squares;
  gl_Position = u_viewproj * vec4(p, 1.0);
}
