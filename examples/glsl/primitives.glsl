// Textbook ray tests for the other kinds, as a shader author writes them (rp_real is float or
// double: docs/shaders.md). Each answers RP_HIT_T with the first contact at t >= 0, or RP_MISS.
//
//   rayproof check --glsl prim=examples/glsl/primitives.glsl
int rp_sphere(rp_vec3 o, rp_vec3 d, rp_vec3 center, rp_real radius, out rp_real t) {
  rp_vec3 oc = o - center;
  rp_real a = dot(d, d), b = dot(oc, d), c = dot(oc, oc) - radius * radius;
  rp_real disc = b * b - a * c;
  if (disc < rp_real(0)) return RP_MISS;
  rp_real s = sqrt(disc);
  rp_real t0 = (-b - s) / a, t1 = (-b + s) / a;
  t = t0 >= rp_real(0) ? t0 : t1;
  return t >= rp_real(0) ? RP_HIT_T : RP_MISS;
}

int rp_box(rp_vec3 o, rp_vec3 d, rp_vec3 lo, rp_vec3 hi, out rp_real t) {
  rp_vec3 inv = rp_real(1) / d;  // d = 0 on an axis: +-inf, and 0 * inf = NaN where o is on a face
  rp_vec3 a = (lo - o) * inv, b = (hi - o) * inv;
  rp_vec3 n = min(a, b), f = max(a, b);
  rp_real t0 = max(max(n.x, n.y), n.z), t1 = min(min(f.x, f.y), f.z);
  if (!(t0 <= t1) || t1 < rp_real(0)) return RP_MISS;
  t = max(t0, rp_real(0));
  return RP_HIT_T;
}

int rp_plane(rp_vec3 o, rp_vec3 d, rp_vec3 point, rp_vec3 normal, out rp_real t) {
  rp_real den = dot(normal, d);
  if (den == rp_real(0)) return RP_MISS;
  t = dot(normal, point - o) / den;
  return t >= rp_real(0) ? RP_HIT_T : RP_MISS;
}

int rp_ellipsoid(rp_vec3 o, rp_vec3 d, rp_vec3 center, rp_vec3 semi_axes, out rp_real t) {
  // Scale to the unit sphere.
  rp_vec3 oc = (o - center) / semi_axes, ds = d / semi_axes;
  rp_real a = dot(ds, ds), b = dot(oc, ds), c = dot(oc, oc) - rp_real(1);
  rp_real disc = b * b - a * c;
  if (disc < rp_real(0)) return RP_MISS;
  rp_real s = sqrt(disc);
  rp_real t0 = (-b - s) / a, t1 = (-b + s) / a;
  t = t0 >= rp_real(0) ? t0 : t1;
  return t >= rp_real(0) ? RP_HIT_T : RP_MISS;
}

int rp_disk(rp_vec3 o, rp_vec3 d, rp_vec3 center, rp_vec3 normal, rp_real radius, out rp_real t) {
  rp_real den = dot(normal, d);
  if (den == rp_real(0)) return RP_MISS;
  t = dot(normal, center - o) / den;
  if (t < rp_real(0)) return RP_MISS;
  rp_vec3 q = o + t * d - center;
  return dot(q, q) <= radius * radius ? RP_HIT_T : RP_MISS;
}
