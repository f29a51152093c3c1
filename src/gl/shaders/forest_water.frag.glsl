// forest_water.frag.glsl — translucent water, fogged.
#version 450 core
#include "fog.glsl"
in vec3 v_world;
out vec4 o_colour;
void main() {
  o_colour = vec4(fogged(vec3(0.16, 0.32, 0.42), v_world), 0.82);
}
