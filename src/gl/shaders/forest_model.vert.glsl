// forest_model.vert.glsl — the forest's 3D objects, instanced: each instance
// record scales, turns about the vertical and places the model; the wind
// sways it as bbc_forest_wind_offset (src/forest/sun_wind.c) says.
#version 450 core
#include "impostor.glsl"
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_inst;  // x, y, z, yaw
layout(location = 4) in vec2 a_inst2;  // scale, fade
layout(location = 5) in vec4 a_tangent;  // along +u, handedness in w
layout(location = 6) in float a_occlusion;  // where no occlusion map says
uniform mat4 u_viewproj;
uniform vec3 u_wind;  // strength, direction x, z (unit)
uniform float u_time;
uniform float u_sway;  // the model's height (model units); 0 = it does not sway
uniform int u_blend;  // 1: the level's weight from the distance (a cell across a switch)
uniform vec4 u_lod;  // the level's start and end, the model's fade, 1 / zoom
uniform vec3 u_eye;
out vec3 v_world;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
out float v_fade;
out float v_occlusion;
flat out vec4 v_imp_base;  // an impostor: its centre's world position, scale
flat out ivec4 v_imp_fr;   // its three frames (i + n j) and 1
flat out vec3 v_imp_w;     // their weights
flat out vec2 v_imp_cs;    // its yaw's cosine and sine
// bbc_forest_wind_offset: q relative to the base, base its world position
vec3 wind_offset(vec3 q, vec3 base, float height) {
  if (u_wind.x <= 0.0 || height <= 0.0 || q.y <= 0.0) return vec3(0.0);
  vec2 d = u_wind.yz;
  float a = 0.04 * u_wind.x * height;
  float h = min(q.y / height, 2.0);
  float phase = 6.28318531 * fract(0.6180339 * base.x + 0.4142136 * base.z);
  float gust = 0.5 + 0.5 * sin(0.4 * u_time - 0.05 * (base.x * d.x + base.z * d.y));
  float sway = (0.35 + 0.65 * gust) * (1.0 + 0.3 * sin(1.7 * u_time + phase));
  float bend = a * h * h * sway;
  float r = min(length(q.xz) / height, 1.0);
  float flutter = 0.25 * a * r * h * (0.5 + gust) *
                  sin(5.0 * u_time + phase + 3.0 * (q.x + q.y + q.z) / height);
  return vec3(d.x * bend - d.y * 0.8 * flutter, 0.6 * flutter, d.y * bend + d.x * 0.8 * flutter);
}
// bbc_forest_lod_get_weight
float lod_weight(float d) {
  float lo = u_lod.x, hi = u_lod.y, f = u_lod.z;
  if (f <= 0.0) return (d >= lo && d < hi) ? 1.0 : 0.0;
  float win = lo <= 0.0 ? 1.0 : (d - (lo - f)) / f;
  float wout = (hi + f - d) / f;
  return clamp(min(win, wout), 0.0, 1.0);
}
vec3 turn(vec3 v, float c, float s) { return vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); }
void main() {
  v_fade = a_inst2.y;
  if (u_blend != 0) v_fade = lod_weight(distance(a_inst.xyz, u_eye) * u_lod.w);
  if (v_fade <= 0.0) {  // this level does not draw the tree: outside the clip volume
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    return;
  }
  float c = cos(a_inst.w), s = sin(a_inst.w);
  if (u_imp.w != 0) {  // an impostor: its quad across the view through its centre
    vec3 cq = turn(u_imp_c.xyz * a_inst2.x, c, s);
    cq += wind_offset(cq, a_inst.xyz, u_sway * a_inst2.x);
    vec3 cw = a_inst.xyz + cq, e = normalize(u_eye - cw);
    vec3 r = abs(e.y) > 0.999 ? vec3(1.0, 0.0, 0.0) : normalize(cross(vec3(0.0, 1.0, 0.0), e));
    vec3 u = cross(e, r);
    float h = u_imp_c.w * a_inst2.x;
    v_world = cw + (a_pos.x * r + a_pos.y * u) * h;
    v_imp_base = vec4(cw, a_inst2.x);
    v_imp_cs = vec2(c, s);
    ivec2 fr[3];
    imp_blend(turn(e, c, -s), fr, v_imp_w);
    v_imp_fr = ivec4(fr[0].x + u_imp.x * fr[0].y, fr[1].x + u_imp.x * fr[1].y,
                     fr[2].x + u_imp.x * fr[2].y, 1);
    v_normal = e;
    v_tangent = vec4(r, 1.0);
    v_uv = a_uv;
    v_occlusion = 1.0;
    gl_Position = u_viewproj * vec4(v_world, 1.0);
    return;
  }
  vec3 q = turn(a_pos * a_inst2.x, c, s);
  q += wind_offset(q, a_inst.xyz, u_sway * a_inst2.x);
  v_normal = turn(a_normal, c, s);
  v_tangent = vec4(turn(a_tangent.xyz, c, s), a_tangent.w);
  v_world = q + a_inst.xyz;
  v_uv = vec2(a_uv.x, 1.0 - a_uv.y);  // uvs: v up; images: rows top first
  v_occlusion = a_occlusion;
  gl_Position = u_viewproj * vec4(v_world, 1.0);
}
