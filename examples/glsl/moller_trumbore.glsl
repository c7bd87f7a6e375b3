// The worked problems' Möller–Trumbore ray/triangle test as a shader author writes it: built-in
// dot and cross, one division, barycentrics tested against 0. The same formula as the C plugin
// examples/c_plugin/moller_trumbore.c (here in the shader's own precision).
//
//   rayproof check --glsl mt=examples/glsl/moller_trumbore.glsl
//   rayproof check --glsl mt:double=examples/glsl/moller_trumbore.glsl     (where the device has shaderFloat64)
//
// rayproof_real and rayproof_real3 are float and vec3 (or double and dvec3 for NAME:double=FILE): docs/shaders.md.
int rayproof_triangle(rayproof_real3 o, rayproof_real3 d, rayproof_real3 p0, rayproof_real3 p1, rayproof_real3 p2, out rayproof_real t, out rayproof_real2 b) {
  rayproof_real3 e1 = p1 - p0;
  rayproof_real3 e2 = p2 - p0;
  rayproof_real3 s1 = cross(d, e2);
  rayproof_real det = dot(s1, e1);
  if (det == rayproof_real(0)) return RAYPROOF_MISS;  // parallel to the plane (or in it): the naive test misses
  rayproof_real3 s = o - p0;
  rayproof_real3 s2 = cross(s, e1);
  rayproof_real inv = rayproof_real(1) / det;
  t = dot(s2, e2) * inv;
  b.x = dot(s1, s) * inv;
  b.y = dot(s2, d) * inv;
  if (!(b.x >= rayproof_real(0) && b.y >= rayproof_real(0) && rayproof_real(1) - b.x - b.y >= rayproof_real(0) && t >= rayproof_real(0)))
    return RAYPROOF_MISS;
  return RAYPROOF_HIT_TB;
}
