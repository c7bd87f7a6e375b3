/*
 * Moller's triangle/triangle test (T. Moller, "A Fast Triangle-Triangle Intersection Test", JGT
 * 1997) as a game or physics engine writes it: float, the plane distances compared with 0, no
 * epsilon. A rayproof plugin for the kind tritri (rayproof/plugin.h): it answers whether the two
 * closed triangles meet (RAYPROOF_COARSE_HIT) or not (RAYPROOF_COARSE_MISS).
 *
 *   rayproof check --plugin build/plugins/tritri_moller_c.so --expect no-false-negative
 *
 * rayproof finds the contacts it misses: a shared edge or vertex, a vertex on the other's face,
 * coplanar pairs (in float the distances of coplanar vertices are rarely exactly 0, so the 3D
 * branch runs on rounding noise). C89.
 */
#include <rayproof/plugin.h>

typedef struct {
  float x, y, z;
} vec;

static vec at(const float *in, int i) {
  vec v;
  v.x = in[3 * i];
  v.y = in[3 * i + 1];
  v.z = in[3 * i + 2];
  return v;
}
static vec minus(vec a, vec b) {
  vec v;
  v.x = a.x - b.x;
  v.y = a.y - b.y;
  v.z = a.z - b.z;
  return v;
}
static vec cross(vec a, vec b) {
  vec v;
  v.x = a.y * b.z - a.z * b.y;
  v.y = a.z * b.x - a.x * b.z;
  v.z = a.x * b.y - a.y * b.x;
  return v;
}
static float dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static float absf(float x) { return x < 0 ? -x : x; }
static float coord(vec v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

/* Where a triangle (projections p, signed distances d to the other plane) crosses the line of the
 * two planes: the interval [lo, hi]. Returns 0 when every distance is 0 (coplanar). */
static int span(const float p[3], const float d[3], float *lo, float *hi) {
  int solo, a, b;
  float s, t;
  if (d[0] * d[1] > 0) solo = 2;
  else if (d[0] * d[2] > 0) solo = 1;
  else if (d[1] * d[2] > 0 || d[0] != 0) solo = 0;
  else if (d[1] != 0) solo = 1;
  else if (d[2] != 0) solo = 2;
  else return 0;
  a = (solo + 1) % 3;
  b = (solo + 2) % 3;
  s = p[solo] + (p[a] - p[solo]) * d[solo] / (d[solo] - d[a]);
  t = p[solo] + (p[b] - p[solo]) * d[solo] / (d[solo] - d[b]);
  *lo = s < t ? s : t;
  *hi = s < t ? t : s;
  return 1;
}

/* 2D helpers for the coplanar case: the triangles projected by dropping axis `drop`. */
static float turn(const float *a, const float *b, const float *c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}
static int between(const float *a, const float *b, const float *c) { /* c on segment ab, collinear */
  return (c[0] >= (a[0] < b[0] ? a[0] : b[0])) && (c[0] <= (a[0] < b[0] ? b[0] : a[0])) &&
         (c[1] >= (a[1] < b[1] ? a[1] : b[1])) && (c[1] <= (a[1] < b[1] ? b[1] : a[1]));
}
static int segments_meet(const float *a, const float *b, const float *c, const float *d) {
  float s1 = turn(c, d, a), s2 = turn(c, d, b), s3 = turn(a, b, c), s4 = turn(a, b, d);
  if (((s1 > 0 && s2 < 0) || (s1 < 0 && s2 > 0)) && ((s3 > 0 && s4 < 0) || (s3 < 0 && s4 > 0))) return 1;
  return (s1 == 0 && between(c, d, a)) || (s2 == 0 && between(c, d, b)) || (s3 == 0 && between(a, b, c)) ||
         (s4 == 0 && between(a, b, d));
}
static int inside(const float *p, float t[3][2]) {
  float u = turn(t[0], t[1], p), v = turn(t[1], t[2], p), w = turn(t[2], t[0], p);
  return (u >= 0 && v >= 0 && w >= 0) || (u <= 0 && v <= 0 && w <= 0);
}
static int coplanar_meet(vec n, const vec a[3], const vec b[3]) {
  float pa[3][2], pb[3][2];
  int i, j, u, v;
  float nx = absf(n.x), ny = absf(n.y), nz = absf(n.z);
  int drop = (nx >= ny && nx >= nz) ? 0 : (ny >= nz ? 1 : 2);
  u = drop == 0 ? 1 : 0;
  v = drop == 2 ? 1 : 2;
  for (i = 0; i < 3; ++i) {
    pa[i][0] = coord(a[i], u);
    pa[i][1] = coord(a[i], v);
    pb[i][0] = coord(b[i], u);
    pb[i][1] = coord(b[i], v);
  }
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j)
      if (segments_meet(pa[i], pa[(i + 1) % 3], pb[j], pb[(j + 1) % 3])) return 1;
  return inside(pa[0], pb) || inside(pb[0], pa);
}

static int moller(const vec a[3], const vec b[3]) {
  vec na = cross(minus(a[1], a[0]), minus(a[2], a[0]));
  vec nb = cross(minus(b[1], b[0]), minus(b[2], b[0]));
  float da[3], db[3], pa[3], pb[3], lo_a, hi_a, lo_b, hi_b;
  float offset_b = -dot(nb, b[0]), offset_a = -dot(na, a[0]);
  vec line;
  int i, k;
  for (i = 0; i < 3; ++i) da[i] = dot(nb, a[i]) + offset_b; /* a's vertices against b's plane */
  if (da[0] * da[1] > 0 && da[0] * da[2] > 0) return 0;
  for (i = 0; i < 3; ++i) db[i] = dot(na, b[i]) + offset_a;
  if (db[0] * db[1] > 0 && db[0] * db[2] > 0) return 0;
  line = cross(na, nb);
  k = (absf(line.x) >= absf(line.y) && absf(line.x) >= absf(line.z)) ? 0 : (absf(line.y) >= absf(line.z) ? 1 : 2);
  for (i = 0; i < 3; ++i) {
    pa[i] = coord(a[i], k);
    pb[i] = coord(b[i], k);
  }
  if (!span(pa, da, &lo_a, &hi_a) || !span(pb, db, &lo_b, &hi_b)) return coplanar_meet(na, a, b);
  return !(hi_a < lo_b || hi_b < lo_a);
}

static void tritri(const float *in, struct rayproof_answer *out) {
  vec a[3], b[3];
  int i;
  for (i = 0; i < 3; ++i) {
    a[i] = at(in, i);
    b[i] = at(in, 3 + i);
  }
  out->cls = moller(a, b) ? RAYPROOF_COARSE_HIT : RAYPROOF_COARSE_MISS;
}

static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRITRI, 0, tritri}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "tritri-moller-c", RAYPROOF_FLOAT, 1, kinds};

RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
