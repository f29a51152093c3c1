// forest_model.frag.glsl — the objects' materials; levels blended by screen-
// door dithering (a level discards the pixels its fade weight does not
// cover, so no sorting is needed and depth stays right).
#version 450 core
#include "fog.glsl"
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in float v_fade;
uniform sampler2D u_tex;
uniform int u_has_tex; // 0 none, 1 RGBA8, 2 BC1 (transparent texels black)
uniform vec4 u_base;
uniform int u_lit;
uniform vec3 u_light;
uniform int u_fill;
uniform float u_gain;
uniform vec3 u_amb;
out vec4 o_colour;
// 8 x 8 ordered dither: the screen door of the level blending
float bayer(ivec2 p) {
  int v = 0;
  for (int i = 0; i < 3; i++) {
    int x = (p.x >> i) & 1, y = (p.y >> i) & 1;
    v |= (((x ^ y) << 1) | y) << (2 * (2 - i));
  }
  return (float(v) + 0.5) / 64.0;
}
void main() {
  if (v_fade < 1.0 && bayer(ivec2(gl_FragCoord.xy)) >= v_fade) discard;
  vec4 c = u_base;
  vec4 t = u_has_tex != 0 ? texture(u_tex, v_uv) : vec4(1.0);
  // BC1 (2): transparent texels decode black, so filtering mixes black into
  // the edges; divided by the filtered alpha, the colour is the mean of the
  // opaque texels around it, as with the RGBA8 atlas's filled texels (1)
  if (u_has_tex == 2 && t.a > 0.0) t.rgb /= t.a;
  c *= t;
  if (c.a < 0.5) discard;
  // lit as bbcgen bakes its clouds (two-sided Lambert, 0.35 ambient, the
  // model's light gain, X3D viewers' ambient), so that the polygon level
  // and the clouds after it look alike
  if (u_lit != 0)
    c.rgb = c.rgb * (0.35 + 0.65 * abs(dot(normalize(v_normal), u_light))) * u_gain + u_amb;
  o_colour = u_fill != 0 ? vec4(1.0) : vec4(fogged(c.rgb, v_world), 1.0);
}
