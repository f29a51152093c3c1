// forest_water.vert.glsl — the water plane, in world coordinates.
#version 450 core
layout(location = 0) in vec3 a_pos;
uniform mat4 u_viewproj;
out vec3 v_world;
void main() {
  v_world = a_pos;
  gl_Position = u_viewproj * vec4(a_pos, 1.0);
}
