// viewer_line.vert.glsl — coloured lines and triangles (the billboards'
// rectangles, bbc_geometry).
#version 450 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_colour;
uniform mat4 u_mvp;
out vec3 v_colour;
void main() {
  v_colour = a_colour;
  gl_Position = u_mvp * vec4(a_pos, 1.0);
}
