// text.vert.glsl — the text overlay's glyph quads and panel, in pixels.
#version 450 core
layout(location = 0) in vec4 a_v;  // pixel x, y, u, v
uniform vec2 u_size;
out vec2 v_uv;
void main() {
  v_uv = a_v.zw;
  gl_Position = vec4(a_v.x / u_size.x * 2.0 - 1.0,
                     1.0 - a_v.y / u_size.y * 2.0, 0.0, 1.0);
}
