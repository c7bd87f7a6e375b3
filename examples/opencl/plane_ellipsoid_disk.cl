/*
 * Textbook kernels for the other three kinds (plane, axis-aligned ellipsoid, disk), so that every
 * kind of docs/cases.md has an OpenCL C example (docs/opencl.md).
 *     rayproof check --opencl k=examples/opencl/plane_ellipsoid_disk.cl
 */
int rayproof_plane(rayproof_real3 o, rayproof_real3 d, rayproof_real3 p, rayproof_real3 n, rayproof_real* t) {
  const rayproof_real den = dot(d, n);
  if (den == 0) return RAYPROOF_MISS;
  *t = dot(p - o, n) / den;
  return *t >= 0 ? RAYPROOF_HIT_T : RAYPROOF_MISS;
}
int rayproof_ellipsoid(rayproof_real3 o, rayproof_real3 d, rayproof_real3 c, rayproof_real3 s, rayproof_real* t) {
  const rayproof_real3 oc = (o - c) / s, dd = d / s;
  const rayproof_real a = dot(dd, dd), b = dot(oc, dd), k = dot(oc, oc) - 1;
  const rayproof_real disc = b * b - a * k;
  if (disc < 0) return RAYPROOF_MISS;
  const rayproof_real t1 = (-b + sqrt(disc)) / a, t0 = (-b - sqrt(disc)) / a;
  if (t1 < 0) return RAYPROOF_MISS;
  *t = t0 >= 0 ? t0 : t1;
  return RAYPROOF_HIT_T;
}
int rayproof_disk(rayproof_real3 o, rayproof_real3 d, rayproof_real3 c, rayproof_real3 n, rayproof_real r, rayproof_real* t) {
  const rayproof_real den = dot(d, n);
  if (den == 0) return RAYPROOF_MISS;
  const rayproof_real tt = dot(c - o, n) / den;
  if (tt < 0) return RAYPROOF_MISS;
  const rayproof_real3 q = o + tt * d - c;
  if (dot(q, q) > r * r) return RAYPROOF_MISS;
  *t = tt;
  return RAYPROOF_HIT_T;
}
