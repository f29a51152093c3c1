// forest_model.frag.glsl — the objects' materials, lit by the sun as a glTF
// viewer lights a lit material (bbc_forest_sun_shade); levels blended by
// screen-door dithering (a level discards the pixels its fade weight does
// not cover, so no sorting is needed and depth stays right).
#version 450 core
#include "fog.glsl"
#include "impostor.glsl"
in vec3 v_world;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in float v_fade;
in float v_occlusion;
flat in vec4 v_imp_base;
flat in ivec4 v_imp_fr;
flat in vec3 v_imp_w;
flat in vec2 v_imp_cs;
uniform sampler2D u_tex;
uniform sampler2D u_normal;
uniform sampler2D u_occlusion;
uniform int u_has_tex;  // 0 none, 1 RGBA8, 2 BC1 (transparent texels black)
uniform int u_texel_alpha;  // alpha at the nearest texel of the nearest level: 1 always, 2 past level 0
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
// an impostor's texel along the view's ray in frame fr (i + n j) at level
// lv, as bbc_impostor_render finds it (src/raster/impostor_draw.c): marched
// one texel of the frame at a time through the model's sphere, the first
// covered texel the ray reaches within a thin shell, or crosses into from in
// front of its neighbour (alpha 0 or 1 at every level); 0 where none
void imp_look(int fr, int lv, vec3 p, vec3 f, out vec4 col, out vec3 nrm) {
  int n = u_imp.x, S = u_imp_lv[lv].x, row = u_imp_lv[lv].y;
  ivec2 ij = ivec2(fr % n, fr / n);
  vec3 dir, r, u;
  imp_basis(ij, dir, r, u);
  col = vec4(0.0);
  nrm = vec3(0.0);
  float denom = -dot(f, dir);
  if (denom <= 0.02) return;
  float R = u_imp_r, he = u_imp_c.w, k = 0.5 * float(S) / he, a0 = -dot(p, dir);
  vec3 q0 = p + (-R - a0) / denom * f, q1 = p + (R - a0) / denom * f;
  vec2 s0 = vec2(0.5 * float(S) + k * dot(q0, r), 0.5 * float(S) - k * dot(q0, u));
  vec2 s1 = vec2(0.5 * float(S) + k * dot(q1, r), 0.5 * float(S) - k * dot(q1, u));
  float len = max(abs(s1.x - s0.x), abs(s1.y - s0.y));
  int steps = clamp(int(ceil(len)), 1, 512);
  float texel = 2.0 * he / float(S);
  float shell = 2.0 * R / float(steps) + texel + 2.0 * R / 255.0, bridge = 0.5 * he;
  bool front = false;
  float fd = 0.0;
  for (int i = 0; i < steps; i++) {
    float mid = (float(i) + 0.5) / float(steps), end = -R + 2.0 * R * float(i + 1) / float(steps);
    ivec2 x = ivec2(floor(mix(s0, s1, mid)));
    if (any(lessThan(x, ivec2(0))) || any(greaterThanEqual(x, ivec2(S)))) {
      front = false;
      continue;
    }
    ivec2 at = ij * S + x + ivec2(0, row);
    vec4 c = texelFetch(u_tex, at, 0);
    if (c.a < 0.5) {
      front = false;
      continue;
    }
    vec4 m = texelFetch(u_normal, at, 0);
    float d = (m.a * 2.0 - 1.0) * R;
    bool hit = d <= end && (d >= end - shell || (front && fd - d <= bridge));
    front = d > end;
    fd = d;
    if (hit) {
      col = vec4(c.rgb, 1.0);
      nrm = m.xyz * 2.0 - 1.0;
      return;
    }
  }
}
vec3 imp_turn(vec3 v, float c, float s) { return vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); }
// an impostor's fragment: the weighted hits of its three frames, alpha
// tested against an ordered dither (as alpha to coverage), lit by the sun
void impostor(float tpp) {
  float c = v_imp_cs.x, s = v_imp_cs.y;
  // the level whose texels are nearest the pixel's size (bbc_impostor_render)
  tpp *= float(u_imp.z) / (2.0 * u_imp_c.w * v_imp_base.w);
  int lv = tpp > 1.0 ? min(int(floor(log2(tpp) + 0.5)), 15) : 0;
  vec3 p = imp_turn(v_world - v_imp_base.xyz, c, -s) / v_imp_base.w;
  vec3 f = imp_turn(normalize(v_world - u_eye), c, -s);
  vec4 sum = vec4(0.0);
  vec3 nsum = vec3(0.0);
  float wsum = 0.0;
  for (int k = 0; k < 3; k++) {
    if (v_imp_w[k] <= 0.0) continue;
    vec4 col;
    vec3 nrm;
    imp_look(v_imp_fr[k], lv, p, f, col, nrm);
    sum += v_imp_w[k] * col;
    nsum += v_imp_w[k] * nrm;
    wsum += v_imp_w[k];
  }
  if (wsum <= 0.0 || sum.a / wsum < bayer(ivec2(gl_FragCoord.yx) + ivec2(3, 5))) discard;
  vec3 rgb = sum.rgb / sum.a;
  if (u_lit != 0) {
    // the covered frames' mean normal, its length kept (at most 1): n.l of
    // it plus its missing length's share lit as a sphere of normals is (a
    // quarter), as bbc_impostor_render lights it
    vec3 n = sum.a > 0.0 ? nsum / sum.a : vec3(0.0);
    float len = length(n);
    n = len > 1.0 ? n / len : n; // a mean of zero stays zero
    len = min(len, 1.0);
    n = imp_turn(n, c, s);
    rgb *= (u_ambient + max(dot(n, u_light), 0.0) + 0.25 * (1.0 - len)) / (u_ambient + 1.0);
  }
  o_colour = u_fill != 0 ? vec4(1.0) : vec4(fogged(rgb, v_world), 1.0);
}
void main() {
  // a pixel's size on an impostor's quad, taken before any fragment of the
  // quad discards (world units)
  float tpp = max(length(dFdx(v_world)), length(dFdy(v_world)));
  if (v_fade < 1.0 && bayer(ivec2(gl_FragCoord.xy)) >= v_fade) discard;
  if (u_imp.w != 0) {
    impostor(tpp);
    return;
  }
  vec4 c = u_base;
  vec4 t = u_has_tex != 0 ? texture(u_tex, v_uv) : vec4(1.0);
  // BC1 (2): transparent texels decode black, so filtering mixes black into
  // the edges; divided by the filtered alpha, the colour is the mean of the
  // opaque texels around it, as with the RGBA8 atlas's filled texels (1)
  if (u_has_tex == 2 && t.a > 0.0) t.rgb /= t.a;
  c *= t;
  float lq = u_texel_alpha != 0 ? textureQueryLod(u_tex, v_uv).x : 0.0;
  if (u_texel_alpha == 1 || (u_texel_alpha == 2 && lq >= 0.5)) {
    // dithered alpha (a cloud's atlas, any alpha-tested mip level): each
    // opaque texel keeps its whole area (a bilinear test at 0.5 keeps 0.61
    // of an isolated one)
    int l = int(round(lq));
    ivec2 sz = textureSize(u_tex, l);
    ivec2 at = min(ivec2(floor(fract(v_uv) * vec2(sz))), sz - 1);  // wrapped, as GL_REPEAT
    c.a = u_base.a * texelFetch(u_tex, at, l).a;
  }
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
