/*
 * The worked problems' Möller–Trumbore in float, the same formula and order of operations as the
 * OpenCL C example examples/opencl/moller_trumbore.cl (cross and dot written out, one division),
 * built with -ffp-contract=off so that every product is rounded on its own. rayproof's check of the
 * OpenCL kernel compares the device's answers with this C build's (--compare-plugin) and says where
 * and, where it can tell, why they differ (docs/opencl.md).
 *
 * Build (a build of the rayproof tree builds it as build/plugins/moller_trumbore_float_c.so), or alone:
 *     cc -O2 -ffp-contract=off -shared -fPIC -I include examples/c_plugin/moller_trumbore_float.c \
 *        -o moller_trumbore_float_c.so
 */
#include <rayproof/plugin.h>

static void sub(const float *a, const float *b, float *out) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}

static void cross(const float *a, const float *b, float *out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static float dot(const float *a, const float *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* in: o(3) d(3) p0(3) p1(3) p2(3), docs/cases.md order, each rounded to float. */
static void triangle(const float *in, struct rayproof_answer *out) {
  const float *o = in, *d = in + 3, *p0 = in + 6, *p1 = in + 9, *p2 = in + 12;
  float e1[3], e2[3], s[3], s1[3], s2[3];
  float det, inv, t, b1, b2;
  sub(p1, p0, e1);
  sub(p2, p0, e2);
  sub(o, p0, s);
  cross(d, e2, s1);
  det = dot(s1, e1);
  out->cls = RAYPROOF_COARSE_MISS;
  if (det == 0.0f) return; /* parallel to the plane (or in it): the naive test calls it a miss */
  cross(s, e1, s2);
  inv = 1.0f / det;
  t = dot(s2, e2) * inv;
  b1 = dot(s1, s) * inv;
  b2 = dot(s2, d) * inv;
  if (!(b1 >= 0.0f && b2 >= 0.0f && 1.0f - b1 - b2 >= 0.0f && t >= 0.0f)) return;
  out->cls = RAYPROOF_COARSE_HIT;
  out->has = RAYPROOF_HAS_T | RAYPROOF_HAS_B;
  out->t = t;
  out->b1 = b1;
  out->b2 = b2;
}

static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, 0, triangle}};

static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "mt-c-float", RAYPROOF_FLOAT, 1, kinds};

RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
