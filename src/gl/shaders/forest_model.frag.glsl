// forest_model.frag.glsl — the objects' materials, lit by the sun as a glTF
// viewer lights a lit material (bbc_forest_sun_shade); levels blended by
// screen-door dithering (a level discards the pixels its fade weight does
// not cover, so no sorting is needed and depth stays right).
#version 450 core
#include "fog.glsl"
in vec3 v_world;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in float v_fade;
in float v_occlusion;
uniform sampler2D u_tex;
uniform sampler2D u_normal;
uniform sampler2D u_occlusion;
uniform int u_has_tex;  // 0 none, 1 RGBA8, 2 BC1 (transparent texels black)
uniform ivec2 u_maps;   // a normal map, an occlusion map
uniform vec4 u_base;
uniform int u_lit;
uniform vec3 u_light;  // towards the sun
uniform float u_ambient;
uniform int u_fill;
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
  if (u_lit != 0) {
    // the normal bent by the normal map (tangent space: x along +u, y along
    // the bitangent, z the surface's normal), turned to the side seen
    vec3 n = normalize(v_normal);
    if (u_maps.x != 0) {
      vec3 tg = v_tangent.xyz - n * dot(n, v_tangent.xyz);
      if (dot(tg, tg) > 1e-12) {
        tg = normalize(tg);
        vec3 b = cross(n, tg) * (v_tangent.w < 0.0 ? -1.0 : 1.0);
        vec3 m = texture(u_normal, v_uv).xyz * 2.0 - 1.0;
        vec3 bent = tg * m.x + b * m.y + n * m.z;
        if (dot(bent, bent) > 1e-12) n = normalize(bent);
      }
    }
    if (!gl_FrontFacing) n = -n;
    // a cloud's texel keeps the normal its leaf had towards the image's
    // viewer; seen from elsewhere, a two-sided leaf shows the side towards
    // the eye, as the polygon level's leaves do
    if (u_maps.x != 0 && dot(n, u_eye - v_world) < 0.0) n = -n;
    float ao = u_maps.y != 0 ? texture(u_occlusion, v_uv).r : v_occlusion;
    c.rgb *= (u_ambient * ao + max(dot(n, u_light), 0.0)) / (u_ambient + 1.0);
  }
  o_colour = u_fill != 0 ? vec4(1.0) : vec4(fogged(c.rgb, v_world), 1.0);
}
