// forest_model.vert.glsl — the forest's 3D objects, instanced: each instance
// record scales, turns about the vertical and places the model.
#version 450 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_inst;  // x, y, z, yaw
layout(location = 4) in vec2 a_inst2;  // scale, fade
uniform mat4 u_viewproj;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out float v_fade;
void main() {
  float c = cos(a_inst.w), s = sin(a_inst.w);
  vec3 p = a_pos * a_inst2.x;
  p = vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
  v_normal = vec3(c * a_normal.x + s * a_normal.z, a_normal.y, -s * a_normal.x + c * a_normal.z);
  v_world = p + a_inst.xyz;
  v_uv = vec2(a_uv.x, 1.0 - a_uv.y);  // uvs: v up; images: rows top first
  v_fade = a_inst2.y;
  gl_Position = u_viewproj * vec4(v_world, 1.0);
}
