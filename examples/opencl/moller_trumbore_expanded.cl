/*
 * The same Möller–Trumbore as moller_trumbore.cl with cross and dot written out, term by term as
 * in the C plugin examples/c_plugin/moller_trumbore_float.c. OpenCL C contracts `a * b + c` into
 * an FMA by default (FP_CONTRACT ON) where the device has one, so this build answers differently
 * from the C build (-ffp-contract=off) on many cases; `--cl-contract-off` (or
 * `#pragma OPENCL FP_CONTRACT OFF` at the top of this file) makes them agree. rayproof finds both:
 *     rayproof check --opencl mt-cl=examples/opencl/moller_trumbore_expanded.cl \
 *         --compare-plugin build/plugins/moller_trumbore_float_c.so --families tri_edge,tri_generic
 */
int rayproof_triangle(rayproof_real3 o, rayproof_real3 d, rayproof_real3 p0, rayproof_real3 p1,
                      rayproof_real3 p2, rayproof_real* t, rayproof_real* b1, rayproof_real* b2) {
  const rayproof_real3 e1 = p1 - p0, e2 = p2 - p0, s = o - p0;
  const rayproof_real3 s1 =
      (rayproof_real3)(d.y * e2.z - d.z * e2.y, d.z * e2.x - d.x * e2.z, d.x * e2.y - d.y * e2.x);
  const rayproof_real det = s1.x * e1.x + s1.y * e1.y + s1.z * e1.z;
  if (det == 0) return RAYPROOF_MISS; /* parallel to the plane (or in it): the naive test misses */
  const rayproof_real3 s2 =
      (rayproof_real3)(s.y * e1.z - s.z * e1.y, s.z * e1.x - s.x * e1.z, s.x * e1.y - s.y * e1.x);
  const rayproof_real inv = 1 / det;
  *t = (s2.x * e2.x + s2.y * e2.y + s2.z * e2.z) * inv;
  *b1 = (s1.x * s.x + s1.y * s.y + s1.z * s.z) * inv;
  *b2 = (s2.x * d.x + s2.y * d.y + s2.z * d.z) * inv;
  if (!(*b1 >= 0 && *b2 >= 0 && 1 - *b1 - *b2 >= 0 && *t >= 0)) return RAYPROOF_MISS;
  return RAYPROOF_HIT_TB;
}
