/*
 * The C build of examples/glsl/moller_trumbore.glsl: the same formula, in float, every product and
 * sum rounded on its own (-ffp-contract=off), as the GPU build's reference in
 *     rayproof check --glsl mt=examples/glsl/moller_trumbore.glsl --compare-plugin build/plugins/mt_glsl_float_c.so
 * which says where the GPU build answers differently and why (FMA contraction, flushed subnormals).
 * Build alone:  cc -O2 -ffp-contract=off -shared -fPIC -I include examples/glsl/moller_trumbore_float.c -o mt_float.so
 */
#include <rayproof/plugin.h>

struct v3 {
  float x, y, z;
};

static struct v3 sub(struct v3 a, struct v3 b) {
  struct v3 r;
  r.x = a.x - b.x;
  r.y = a.y - b.y;
  r.z = a.z - b.z;
  return r;
}

/* GLSL's cross and dot, evaluated left to right. */
static struct v3 cross(struct v3 a, struct v3 b) {
  struct v3 r;
  r.x = a.y * b.z - b.y * a.z;
  r.y = a.z * b.x - b.z * a.x;
  r.z = a.x * b.y - b.x * a.y;
  return r;
}

static float dot(struct v3 a, struct v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static struct v3 at(const float *p) {
  struct v3 r;
  r.x = p[0];
  r.y = p[1];
  r.z = p[2];
  return r;
}

static void triangle(const float *in, struct rayproof_answer *out) {
  struct v3 o = at(in), d = at(in + 3), p0 = at(in + 6), p1 = at(in + 9), p2 = at(in + 12);
  struct v3 e1 = sub(p1, p0), e2 = sub(p2, p0), s1 = cross(d, e2), s, s2;
  float det = dot(s1, e1), inv, t, b1, b2;
  out->cls = RAYPROOF_COARSE_MISS;
  if (det == 0.0f) return;
  s = sub(o, p0);
  s2 = cross(s, e1);
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

static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "mt-float-c", RAYPROOF_FLOAT, 1, kinds};

RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
