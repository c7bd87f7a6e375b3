/*
 * The worked problems' Möller–Trumbore ray/triangle test as a rayproof plugin, written the naive
 * textbook way (as in include/rayproof/triangle_moller_trumbore.h): one division, barycentrics
 * tested against 0 in double. rayproof catches it with false misses on rays that hit an edge or a
 * vertex exactly, where rounding pushes a barycentric just below 0.
 *
 * Build (a build of the rayproof tree builds it as build/plugins/moller_trumbore_c.so), or alone:
 *     cc -O2 -shared -fPIC -I include examples/c_plugin/moller_trumbore.c -o moller_trumbore_c.so
 * Run:
 *     rayproof gen tri_edge -n 1000 > edge.txt
 *     rayproof verify --methods double --plugin mt-c=./moller_trumbore_c.so edge.txt
 */
#include <rayproof/plugin.h>

static void sub(const double *a, const double *b, double *out) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}

static void cross(const double *a, const double *b, double *out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* in: o(3) d(3) p0(3) p1(3) p2(3), docs/cases.md order. */
static void triangle(const double *in, struct rayproof_answer *out) {
  const double *o = in, *d = in + 3, *p0 = in + 6, *p1 = in + 9, *p2 = in + 12;
  double e1[3], e2[3], s[3], s1[3], s2[3];
  double det, inv, t, b1, b2;
  sub(p1, p0, e1);
  sub(p2, p0, e2);
  sub(o, p0, s);
  cross(d, e2, s1);
  det = dot(s1, e1);
  out->cls = RAYPROOF_COARSE_MISS;
  if (det == 0.0) return; /* ray parallel to the plane (or in it): the naive test calls it a miss */
  cross(s, e1, s2);
  inv = 1.0 / det;
  t = dot(s2, e2) * inv;
  b1 = dot(s1, s) * inv;
  b2 = dot(s2, d) * inv;
  if (!(b1 >= 0.0 && b2 >= 0.0 && 1.0 - b1 - b2 >= 0.0 && t >= 0.0)) return;
  out->cls = RAYPROOF_COARSE_HIT;
  out->has = RAYPROOF_HAS_T | RAYPROOF_HAS_B;
  out->t = t;
  out->b1 = b1;
  out->b2 = b2;
}

static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, triangle, 0}};

static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "mt-c", RAYPROOF_DOUBLE, 1, kinds};

RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
