// fog.glsl — the forest's distance fog, shared by the terrain, object and
// water fragment shaders (#include "fog.glsl" right after #version).
uniform vec3 u_eye;
uniform vec3 u_fog_colour;
uniform vec2 u_fog;  // start, end; end <= start: no fog
vec3 fogged(vec3 c, vec3 world) {
  if (u_fog.y <= u_fog.x) return c;
  float f = clamp((distance(world, u_eye) - u_fog.x) / (u_fog.y - u_fog.x), 0.0, 1.0);
  return mix(c, u_fog_colour, f);
}
