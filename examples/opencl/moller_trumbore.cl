/*
 * The worked problems' Möller–Trumbore ray/triangle test in OpenCL C, written as a kernel author
 * would: the built-in cross and dot, one division, barycentrics tested against 0. The same formula
 * as the C plugin examples/c_plugin/moller_trumbore_float.c; rayproof runs both and says where the
 * device build answers differently (docs/opencl.md, "The device against the C build").
 *
 * rayproof wraps this function in a __kernel (one work-item per case) and runs it on an OpenCL
 * device; rayproof_real is float, or double with --opencl NAME:double=FILE.
 *     rayproof check --opencl mt-cl=examples/opencl/moller_trumbore.cl --families tri_edge
 */
int rayproof_triangle(rayproof_real3 o, rayproof_real3 d, rayproof_real3 p0, rayproof_real3 p1,
                      rayproof_real3 p2, rayproof_real* t, rayproof_real* b1, rayproof_real* b2) {
  const rayproof_real3 e1 = p1 - p0, e2 = p2 - p0, s = o - p0;
  const rayproof_real3 s1 = cross(d, e2);
  const rayproof_real det = dot(s1, e1);
  if (det == 0) return RAYPROOF_MISS; /* parallel to the plane (or in it): the naive test misses */
  const rayproof_real3 s2 = cross(s, e1);
  const rayproof_real inv = 1 / det;
  *t = dot(s2, e2) * inv;
  *b1 = dot(s1, s) * inv;
  *b2 = dot(s2, d) * inv;
  if (!(*b1 >= 0 && *b2 >= 0 && 1 - *b1 - *b2 >= 0 && *t >= 0)) return RAYPROOF_MISS;
  return RAYPROOF_HIT_TB;
}
