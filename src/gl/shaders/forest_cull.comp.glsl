// forest_cull.comp.glsl — GPU culling: one invocation per static record of one
// model: the frustum test, then a record per level with a weight, appended
// to the level's region of the output (atomic counters per bucket; the last
// counter counts trees whose first component is drawn).
#version 450 core
layout(local_size_x = 256) in;
struct rec { float x, y, z, yaw, scale, fade; };
layout(std430, binding = 0) readonly buffer statics_b { rec statics[]; };
layout(std430, binding = 1) writeonly buffer out_b { rec outr[]; };
layout(std430, binding = 2) buffer counter_b { uint counter[]; };
layout(std430, binding = 3) readonly buffer first_b { uint first_bits[]; };
uniform uint u_first, u_count, u_bucket0, u_trees;
uniform vec4 u_planes[6];
uniform vec3 u_eye;
uniform float u_zoom, u_radius, u_fade;
uniform int u_lods;
uniform vec2 u_range[8];
uniform uint u_base[8];
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  uint k = u_first + i;
  rec r = statics[k];
  vec3 p = vec3(r.x, r.y, r.z);
  float rad = u_radius * r.scale;
  for (int j = 0; j < 6; j++)
    if (dot(u_planes[j].xyz, p) + u_planes[j].w < -rad) return;
  float d = distance(p, u_eye) / u_zoom;
  bool drawn = false;
  for (int l = 0; l < u_lods; l++) {
    float lo = u_range[l].x, hi = u_range[l].y, w;
    if (u_fade <= 0.0) w = (d >= lo && d < hi) ? 1.0 : 0.0;
    else w = clamp(min(lo <= 0.0 ? 1.0 : (d - (lo - u_fade)) / u_fade,
                       (hi + u_fade - d) / u_fade), 0.0, 1.0);
    if (w <= 0.0) continue;
    uint slot = atomicAdd(counter[u_bucket0 + uint(l)], 1u);
    r.fade = w;
    outr[u_base[l] + slot] = r;
    drawn = true;
  }
  if (drawn && ((first_bits[k >> 5] >> (k & 31u)) & 1u) != 0u)
    atomicAdd(counter[u_trees], 1u);
}
