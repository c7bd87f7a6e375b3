/*
 * Textbook kernels for two more kinds, written as a shader author would: the slab test for an
 * axis-aligned box, the quadratic for a sphere (built-in dot and sqrt). Float by default; double with
 * --opencl NAME:double=FILE (docs/opencl.md).
 *     rayproof check --opencl k=examples/opencl/box_sphere.cl --families box_generic,sph_generic
 */
int rayproof_box(rayproof_real3 o, rayproof_real3 d, rayproof_real3 lo, rayproof_real3 hi, rayproof_real* t) {
  const rayproof_real3 inv = 1 / d;
  const rayproof_real3 a = (lo - o) * inv, b = (hi - o) * inv;
  const rayproof_real3 n = fmin(a, b), f = fmax(a, b);
  const rayproof_real t0 = fmax(fmax(n.x, n.y), n.z), t1 = fmin(fmin(f.x, f.y), f.z);
  if (!(t0 <= t1) || t1 < 0) return RAYPROOF_MISS;
  *t = t0 >= 0 ? t0 : t1;
  return RAYPROOF_HIT_T;
}
int rayproof_sphere(rayproof_real3 o, rayproof_real3 d, rayproof_real3 c, rayproof_real r, rayproof_real* t) {
  const rayproof_real3 oc = o - c;
  const rayproof_real a = dot(d, d), b = dot(oc, d), k = dot(oc, oc) - r * r;
  const rayproof_real disc = b * b - a * k;
  if (disc < 0) return RAYPROOF_MISS;
  const rayproof_real s = sqrt(disc);
  const rayproof_real t0 = (-b - s) / a, t1 = (-b + s) / a;
  if (t1 < 0) return RAYPROOF_MISS;
  *t = t0 >= 0 ? t0 : t1;
  return RAYPROOF_HIT_T;
}
