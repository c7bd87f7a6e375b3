// examples/glsl/moller_trumbore.glsl with `precise` on every local, as a shader author keeps the
// compiler from contracting multiply-adds into FMA (GLSL 4.50 refuses `precise` on return types and
// parameters, so the out parameters are assigned from precise locals). On a device that contracts
// the plain version, this one answers as the C build examples/glsl/moller_trumbore_float.c does;
// `rayproof check --glsl-precise` gets the same effect without editing the shader.
int rp_triangle(rp_vec3 o, rp_vec3 d, rp_vec3 p0, rp_vec3 p1, rp_vec3 p2, out rp_real t, out rp_vec2 b) {
  precise rp_vec3 e1 = p1 - p0;
  precise rp_vec3 e2 = p2 - p0;
  precise rp_vec3 s1 = cross(d, e2);
  precise rp_real det = dot(s1, e1);
  if (det == rp_real(0)) return RP_MISS;
  precise rp_vec3 s = o - p0;
  precise rp_vec3 s2 = cross(s, e1);
  precise rp_real inv = rp_real(1) / det;
  precise rp_real tt = dot(s2, e2) * inv;
  precise rp_real b1 = dot(s1, s) * inv;
  precise rp_real b2 = dot(s2, d) * inv;
  precise rp_real rest = rp_real(1) - b1 - b2;
  t = tt;
  b = rp_vec2(b1, b2);
  if (!(b1 >= rp_real(0) && b2 >= rp_real(0) && rest >= rp_real(0) && tt >= rp_real(0))) return RP_MISS;
  return RP_HIT_T_B;
}
