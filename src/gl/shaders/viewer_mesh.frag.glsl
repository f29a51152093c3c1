// viewer_mesh.frag.glsl — lit as bbcgen bakes (two-sided Lambert, 0.35
// ambient) by a headlight; prelit clouds (unlit materials) as they are.
#version 450 core
in vec3 v_normal;
in vec2 v_uv;
uniform sampler2D u_tex;
uniform int u_has_tex, u_unlit, u_lighting;
uniform vec4 u_base;
uniform vec3 u_light;
out vec4 o_colour;
void main() {
  vec4 c = u_base;
  if (u_has_tex != 0) c *= texture(u_tex, v_uv);
  if (c.a < 0.5) discard;
  if (u_unlit == 0 && u_lighting != 0)
    c.rgb *= 0.35 + 0.65 * abs(dot(normalize(v_normal), u_light));
  o_colour = vec4(c.rgb, 1.0);
}
