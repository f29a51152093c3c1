// forest_cmdfill.comp.glsl — after the culling, each indirect draw command
// takes its bucket's count as its instance count.
#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 2) readonly buffer counter_b { uint counter[]; };
layout(std430, binding = 4) buffer cmd_b { uint cmd[]; };
layout(std430, binding = 5) readonly buffer cmdb_b { uint cmd_bucket[]; };
uniform uint u_ncmd;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < u_ncmd) cmd[5u * i + 1u] = counter[cmd_bucket[i]];
}
