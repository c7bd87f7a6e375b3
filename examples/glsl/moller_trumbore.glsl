// The worked problems' Möller–Trumbore ray/triangle test as a shader author writes it: built-in
// dot and cross, one division, barycentrics tested against 0. The same formula as the C plugin
// examples/c_plugin/moller_trumbore.c (here in the shader's own precision).
//
//   rayproof check --glsl mt=examples/glsl/moller_trumbore.glsl
//   rayproof check --glsl mt:double=examples/glsl/moller_trumbore.glsl     (where the device has shaderFloat64)
//
// rp_real and rp_vec3 are float and vec3 (or double and dvec3 for NAME:double=FILE): docs/shaders.md.
int rp_triangle(rp_vec3 o, rp_vec3 d, rp_vec3 p0, rp_vec3 p1, rp_vec3 p2, out rp_real t, out rp_vec2 b) {
  rp_vec3 e1 = p1 - p0;
  rp_vec3 e2 = p2 - p0;
  rp_vec3 s1 = cross(d, e2);
  rp_real det = dot(s1, e1);
  if (det == rp_real(0)) return RP_MISS;  // parallel to the plane (or in it): the naive test misses
  rp_vec3 s = o - p0;
  rp_vec3 s2 = cross(s, e1);
  rp_real inv = rp_real(1) / det;
  t = dot(s2, e2) * inv;
  b.x = dot(s1, s) * inv;
  b.y = dot(s2, d) * inv;
  if (!(b.x >= rp_real(0) && b.y >= rp_real(0) && rp_real(1) - b.x - b.y >= rp_real(0) && t >= rp_real(0)))
    return RP_MISS;
  return RP_HIT_T_B;
}
