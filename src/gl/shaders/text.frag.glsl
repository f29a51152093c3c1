// text.frag.glsl — the font's texels (u < 0: the dark panel behind the text).
#version 450 core
in vec2 v_uv;
uniform sampler2D u_font;
uniform vec4 u_colour;
out vec4 o_colour;
void main() {
  if (v_uv.x < 0.0) { o_colour = vec4(0.0, 0.0, 0.0, 0.55); return; }
  if (texelFetch(u_font, ivec2(v_uv), 0).r < 0.5) discard;
  o_colour = u_colour;
}
