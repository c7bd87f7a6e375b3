// Textbook ray tests for the other kinds, as a shader author writes them (rayproof_real is float or
// double: docs/shaders.md). Each answers RAYPROOF_HIT_T with the first contact at t >= 0, or RAYPROOF_MISS.
//
//   rayproof check --glsl prim=examples/glsl/primitives.glsl
int rayproof_sphere(rayproof_real3 o, rayproof_real3 d, rayproof_real3 center, rayproof_real radius, out rayproof_real t) {
  rayproof_real3 oc = o - center;
  rayproof_real a = dot(d, d), b = dot(oc, d), c = dot(oc, oc) - radius * radius;
  rayproof_real disc = b * b - a * c;
  if (disc < rayproof_real(0)) return RAYPROOF_MISS;
  rayproof_real s = sqrt(disc);
  rayproof_real t0 = (-b - s) / a, t1 = (-b + s) / a;
  t = t0 >= rayproof_real(0) ? t0 : t1;
  return t >= rayproof_real(0) ? RAYPROOF_HIT_T : RAYPROOF_MISS;
}

int rayproof_box(rayproof_real3 o, rayproof_real3 d, rayproof_real3 lo, rayproof_real3 hi, out rayproof_real t) {
  rayproof_real3 inv = rayproof_real(1) / d;  // d = 0 on an axis: +-inf, and 0 * inf = NaN where o is on a face
  rayproof_real3 a = (lo - o) * inv, b = (hi - o) * inv;
  rayproof_real3 n = min(a, b), f = max(a, b);
  rayproof_real t0 = max(max(n.x, n.y), n.z), t1 = min(min(f.x, f.y), f.z);
  if (!(t0 <= t1) || t1 < rayproof_real(0)) return RAYPROOF_MISS;
  t = max(t0, rayproof_real(0));
  return RAYPROOF_HIT_T;
}

int rayproof_plane(rayproof_real3 o, rayproof_real3 d, rayproof_real3 point, rayproof_real3 normal, out rayproof_real t) {
  rayproof_real den = dot(normal, d);
  if (den == rayproof_real(0)) return RAYPROOF_MISS;
  t = dot(normal, point - o) / den;
  return t >= rayproof_real(0) ? RAYPROOF_HIT_T : RAYPROOF_MISS;
}

int rayproof_ellipsoid(rayproof_real3 o, rayproof_real3 d, rayproof_real3 center, rayproof_real3 semi_axes, out rayproof_real t) {
  // Scale to the unit sphere.
  rayproof_real3 oc = (o - center) / semi_axes, ds = d / semi_axes;
  rayproof_real a = dot(ds, ds), b = dot(oc, ds), c = dot(oc, oc) - rayproof_real(1);
  rayproof_real disc = b * b - a * c;
  if (disc < rayproof_real(0)) return RAYPROOF_MISS;
  rayproof_real s = sqrt(disc);
  rayproof_real t0 = (-b - s) / a, t1 = (-b + s) / a;
  t = t0 >= rayproof_real(0) ? t0 : t1;
  return t >= rayproof_real(0) ? RAYPROOF_HIT_T : RAYPROOF_MISS;
}

int rayproof_disk(rayproof_real3 o, rayproof_real3 d, rayproof_real3 center, rayproof_real3 normal, rayproof_real radius, out rayproof_real t) {
  rayproof_real den = dot(normal, d);
  if (den == rayproof_real(0)) return RAYPROOF_MISS;
  t = dot(normal, center - o) / den;
  if (t < rayproof_real(0)) return RAYPROOF_MISS;
  rayproof_real3 q = o + t * d - center;
  return dot(q, q) <= radius * radius ? RAYPROOF_HIT_T : RAYPROOF_MISS;
}
