// impostor.glsl — an octahedral impostor's frames (docs/impostors.md;
// bbc_octahedral_* and bbc_impostor_frame_basis in src/base/octahedral.c):
// the direction of a point of the square, the three frames a view blends,
// and a frame's camera. Up is +y.
uniform ivec4 u_imp;    // frames, hemi, frame_size, 1 = the part is an impostor
uniform vec4 u_imp_c;   // the model's sphere's centre (model units), half_extent
uniform float u_imp_r;  // the sphere's radius
// level l's frame size and first row in the packed atlases (BBCGL_IMP_LEVELS;
// past the last level: the last)
uniform ivec2 u_imp_lv[16];
float imp_sign(float v) { return v < 0.0 ? -1.0 : 1.0; }
vec2 imp_encode(vec3 d) {
  float a = d.x, b = d.z, up = d.y, s = abs(a) + abs(b) + abs(up);
  if (s <= 0.0) return vec2(0.5);
  a /= s;
  b /= s;
  up /= s;
  vec2 p;
  if (u_imp.y != 0) {
    if (up < 0.0) {
      float t = abs(a) + abs(b);
      if (t > 0.0) {
        a /= t;
        b /= t;
      }
    }
    p = vec2(a + b, a - b);
  } else if (up >= 0.0) {
    p = vec2(a, b);
  } else {
    p = vec2((1.0 - abs(b)) * imp_sign(a), (1.0 - abs(a)) * imp_sign(b));
  }
  return 0.5 * p + 0.5;
}
vec3 imp_decode(vec2 uv) {
  vec2 p = 2.0 * uv - 1.0;
  float a, b, up;
  if (u_imp.y != 0) {
    a = 0.5 * (p.x + p.y);
    b = 0.5 * (p.x - p.y);
    up = 1.0 - abs(a) - abs(b);
  } else {
    a = p.x;
    b = p.y;
    up = 1.0 - abs(p.x) - abs(p.y);
    if (up < 0.0) {
      a = (1.0 - abs(p.y)) * imp_sign(p.x);
      b = (1.0 - abs(p.x)) * imp_sign(p.y);
    }
  }
  return normalize(vec3(a, up, b));
}
// the frames (i, j) and weights a view from direction d (towards the viewer) blends
void imp_blend(vec3 d, out ivec2 fr[3], out vec3 w) {
  int n = u_imp.x;
  vec2 g = imp_encode(d) * float(n - 1);
  ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(n - 2));
  vec2 f = g - vec2(c);
  fr[0] = c;
  fr[2] = c + ivec2(1);
  if (f.x >= f.y) {
    fr[1] = c + ivec2(1, 0);
    w = vec3(1.0 - f.x, f.x - f.y, f.y);
  } else {
    fr[1] = c + ivec2(0, 1);
    w = vec3(1.0 - f.y, f.y - f.x, f.x);
  }
}
// frame (i, j): the direction towards its viewer, its image's right and up
void imp_basis(ivec2 ij, out vec3 dir, out vec3 r, out vec3 u) {
  dir = imp_decode(vec2(ij) / float(u_imp.x - 1));
  vec3 f = -dir, hint = abs(dir.y) > 0.999 ? vec3(0.0, 0.0, -1.0) : vec3(0.0, 1.0, 0.0);
  r = normalize(cross(f, hint));
  u = cross(r, f);
}
