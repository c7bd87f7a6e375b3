// examples/glsl/moller_trumbore.glsl with `precise` on every local, as a shader author keeps the
// compiler from contracting multiply-adds into FMA (GLSL 4.50 refuses `precise` on return types and
// parameters, so the out parameters are assigned from precise locals). On a device that contracts
// the plain version, this one answers as the C build examples/glsl/moller_trumbore_float.c does;
// `rayproof check --glsl-precise` gets the same effect without editing the shader.
int rayproof_triangle(rayproof_real3 o, rayproof_real3 d, rayproof_real3 p0, rayproof_real3 p1, rayproof_real3 p2, out rayproof_real t, out rayproof_real2 b) {
  precise rayproof_real3 e1 = p1 - p0;
  precise rayproof_real3 e2 = p2 - p0;
  precise rayproof_real3 s1 = cross(d, e2);
  precise rayproof_real det = dot(s1, e1);
  if (det == rayproof_real(0)) return RAYPROOF_MISS;
  precise rayproof_real3 s = o - p0;
  precise rayproof_real3 s2 = cross(s, e1);
  precise rayproof_real inv = rayproof_real(1) / det;
  precise rayproof_real tt = dot(s2, e2) * inv;
  precise rayproof_real b1 = dot(s1, s) * inv;
  precise rayproof_real b2 = dot(s2, d) * inv;
  precise rayproof_real rest = rayproof_real(1) - b1 - b2;
  t = tt;
  b = rayproof_real2(b1, b2);
  if (!(b1 >= rayproof_real(0) && b2 >= rayproof_real(0) && rest >= rayproof_real(0) && tt >= rayproof_real(0))) return RAYPROOF_MISS;
  return RAYPROOF_HIT_TB;
}
