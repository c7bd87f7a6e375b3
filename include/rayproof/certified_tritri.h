#pragma once
/// The exact triangle/triangle classifier of docs/tritri.md, written once over a sign source: every
/// decision is the sign of orient3d or orient2d on input coordinates, so the class is exact exactly
/// when the signs are. certified/tritri.h runs it on the filtered signs of rayproof/orient.h
/// (try_tritri: undecided when a sign is kUnknown) and on the always-decided signs of the GMP
/// fallback (tritri). Header-only, no dependencies.
///
/// With n_a = (p1 - p0) x (p2 - p0), t_i = orient3d(q0, q1, q2, p_i) and s_i = orient3d(p0, p1, p2, q_i):
///  - all t of one strict sign, or all s: the planes separate them (disjoint);
///  - all s zero: coplanar, decided in 2D (coplanar_class);
///  - else each triangle meets the line L of the two planes on a segment (or a point) whose ends
///    lie on its edges (or vertices): I_a's ends X on edges (a, b) of a with t_a, t_b of opposite
///    closed signs, I_b's ends Y on edges (c, d) of b. Along D = n_a x n_b,
///      sign(D . (Y - X)) = orient3d(p_a, p_b, q_c, q_d) * sign(t_b - t_a) * sign(s_d - s_c)
///    (docs/tritri.md derives it), so the ends of I_a and I_b compare by signs alone.
#include <optional>
#include <utility>

#include "rayproof/orient.h"
#include "rayproof/triangle_common.h"
#include "rayproof/tritri_class.h"

namespace rayproof::certified::tritri_detail {

/// A sign source: o3(a, b, c, d) and o2(au, av, bu, bv, pu, pv) return -1, 0, 1 or
/// orient::kUnknown. Signs records whether any was unknown (the class is then undecided).
template <class O3, class O2>
struct Signs {
  O3 o3f;
  O2 o2f;
  bool unknown = false;
  int o3(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& d) {
    // Two equal points (a shared vertex of a mesh): exactly 0, without the expansions' proof of it.
    if (a == b || a == c || a == d || b == c || b == d || c == d) return 0;
    const int s = o3f(a, b, c, d);
    if (s == orient::kUnknown) unknown = true;
    return s == orient::kUnknown ? 0 : s;
  }
  int o2(double au, double av, double bu, double bv, double pu, double pv) {
    const int s = o2f(au, av, bu, bv, pu, pv);
    if (s == orient::kUnknown) unknown = true;
    return s == orient::kUnknown ? 0 : s;
  }
};

/// Zero area: the three coordinate projections of (p0, p1, p2) all have orient2d = 0 (the cross
/// product of the edges is the zero vector).
template <class S>
bool zero_area(S& sg, const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2) {
  for (int k = 0; k < 3; ++k) {
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    if (sg.o2(p0[u], p0[v], p1[u], p1[v], p2[u], p2[v]) != 0) return false;
  }
  return true;
}

/// All three signs strictly one way (all > 0 or all < 0).
inline bool one_strict_side(const int (&s)[3]) {
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

/// Coplanar, both of positive area: in the coordinate plane of the first axis whose projection of a
/// has orient2d != 0 (the projection is then one-to-one on the common plane), with o_a, o_b the
/// orientations of a and b there and side(e, x) = o * orient2d(edge e, x) (> 0: strictly inside e's
/// line). disjoint: some edge has the other's three vertices strictly outside; coplanar_overlap: no
/// edge has them all on the closed outside (separating-axis theorem for the closed, resp. open,
/// triangles); coplanar_touching otherwise.
template <class S>
TriTri coplanar_class(S& sg, const Vec3<double> (&a)[3], const Vec3<double> (&b)[3]) {
  int u = 0, v = 1, oa = 0;
  for (int k : {2, 0, 1}) {
    u = (k + 1) % 3;
    v = (k + 2) % 3;
    oa = sg.o2(a[0][u], a[0][v], a[1][u], a[1][v], a[2][u], a[2][v]);
    if (oa != 0) break;
  }
  const int ob = sg.o2(b[0][u], b[0][v], b[1][u], b[1][v], b[2][u], b[2][v]);
  bool separated = false, weakly_separated = false;
  auto edges_of = [&](const Vec3<double>(&t)[3], int o, const Vec3<double>(&other)[3]) {
    for (int e = 0; e < 3; ++e) {
      const Vec3<double>&p = t[e], &q = t[(e + 1) % 3];
      int outside = 0, closed_outside = 0;
      for (const Vec3<double>& x : other) {
        const int side = o * sg.o2(p[u], p[v], q[u], q[v], x[u], x[v]);
        outside += side < 0;
        closed_outside += side <= 0;
      }
      separated = separated || outside == 3;
      weakly_separated = weakly_separated || closed_outside == 3;
    }
  };
  edges_of(a, oa, b);
  edges_of(b, ob, a);
  if (separated) return TriTri::disjoint;
  return weakly_separated ? TriTri::coplanar_touching : TriTri::coplanar_overlap;
}

/// The ends of a triangle's segment on L, each as an edge (i, j) whose line meets the other plane
/// at the end (a vertex on the plane is (i, j) with s_j != 0), and sign(s_j - s_i). Returns how many
/// (1 or 2); needs s neither all zero nor of one strict sign.
inline int segment_ends(const int (&s)[3], int (&ends)[2][2], int (&dir)[2]) {
  int n = 0;
  for (int i = 0; i < 3 && n < 2; ++i) {
    if (s[i] == 0) {  // the vertex itself; a partner off the plane exists
      const int j = s[(i + 1) % 3] != 0 ? (i + 1) % 3 : (i + 2) % 3;
      ends[n][0] = i;
      ends[n][1] = j;
      dir[n++] = s[j];
    }
  }
  for (int i = 0; i < 3 && n < 2; ++i) {
    const int j = (i + 1) % 3;
    if (s[i] * s[j] < 0) {  // the edge crosses the plane strictly inside
      ends[n][0] = i;
      ends[n][1] = j;
      dir[n++] = s[j];
    }
  }
  return n;
}

template <class S>
std::optional<TriTri> classify(S& sg, const Triangle<double>& ta, const Triangle<double>& tb) {
  if (!triangle_finite(ta) || !triangle_finite(tb)) return TriTri::invalid;
  const Vec3<double> p[3] = {ta.p0, ta.p1, ta.p2}, q[3] = {tb.p0, tb.p1, tb.p2};
  const bool degenerate = zero_area(sg, p[0], p[1], p[2]) || zero_area(sg, q[0], q[1], q[2]);
  if (sg.unknown) return std::nullopt;
  if (degenerate) return TriTri::degenerate;
  const int t[3] = {sg.o3(q[0], q[1], q[2], p[0]), sg.o3(q[0], q[1], q[2], p[1]), sg.o3(q[0], q[1], q[2], p[2])};
  const int s[3] = {sg.o3(p[0], p[1], p[2], q[0]), sg.o3(p[0], p[1], p[2], q[1]), sg.o3(p[0], p[1], p[2], q[2])};
  if (sg.unknown) return std::nullopt;
  if (one_strict_side(t) || one_strict_side(s)) return TriTri::disjoint;
  if (s[0] == 0 && s[1] == 0 && s[2] == 0) {
    const TriTri c = coplanar_class(sg, p, q);
    if (sg.unknown) return std::nullopt;
    return c;
  }
  int ea[2][2], eb[2][2], da[2], db[2];
  const int na = segment_ends(t, ea, da), nb = segment_ends(s, eb, db);
  int pos = 0, neg = 0;  // comparisons with X before Y, after Y
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) {
      const int c = sg.o3(p[ea[i][0]], p[ea[i][1]], q[eb[j][0]], q[eb[j][1]]) * da[i] * db[j];
      pos += c > 0;
      neg += c < 0;
    }
  if (sg.unknown) return std::nullopt;
  const int pairs = na * nb;
  if (pos == pairs || neg == pairs) return TriTri::disjoint;  // I_a wholly before or after I_b
  // Interior to both: each triangle's plane cuts the other through its interior (vertices strictly
  // on both sides), and the open segments overlap (neither lies wholly on the closed side of the other).
  auto straddles = [](const int (&x)[3]) {
    return (x[0] > 0 || x[1] > 0 || x[2] > 0) && (x[0] < 0 || x[1] < 0 || x[2] < 0);
  };
  if (straddles(t) && straddles(s) && pos > 0 && neg > 0) return TriTri::crossing;
  return TriTri::touching;
}

// ---- contact for any finite pair, zero-area triangles included ----

/// A triangle as the point set it is: a point (n = 1), a segment (n = 2: its two extreme vertices),
/// or a triangle of positive area (n = 3).
struct Simplex {
  int n = 3;
  Vec3<double> v[3];
};

/// An axis along which a and b differ (a != b), and whether x lies between them on it.
inline int varying_axis(const Vec3<double>& a, const Vec3<double>& b) { return a.x != b.x ? 0 : (a.y != b.y ? 1 : 2); }
inline bool between(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& x, int k) {
  return (a[k] <= x[k] && x[k] <= b[k]) || (b[k] <= x[k] && x[k] <= a[k]);
}

template <class S>
Simplex reduce(S& sg, const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2) {
  if (!zero_area(sg, p0, p1, p2)) return {3, {p0, p1, p2}};
  if (p0 == p1 && p1 == p2) return {1, {p0, p0, p0}};
  // Collinear: the extremes along an axis on which the three are not all equal are the segment's ends.
  const int k = p0 == p1 ? varying_axis(p0, p2) : varying_axis(p0, p1);
  const Vec3<double>* lo = &p0;
  const Vec3<double>* hi = &p0;
  for (const Vec3<double>* p : {&p1, &p2}) {
    if ((*p)[k] < (*lo)[k]) lo = p;
    if ((*p)[k] > (*hi)[k]) hi = p;
  }
  return {2, {*lo, *hi, *hi}};
}

/// The coordinate plane (u, v) on which triangle t projects with orient2d != 0, and that sign.
template <class S>
int projection(S& sg, const Vec3<double> (&t)[3], int& u, int& v) {
  for (int k : {2, 0, 1}) {
    u = (k + 1) % 3;
    v = (k + 2) % 3;
    const int o = sg.o2(t[0][u], t[0][v], t[1][u], t[1][v], t[2][u], t[2][v]);
    if (o != 0) return o;
  }
  return 0;
}

/// Point x of t's plane in the closed triangle t (positive area).
template <class S>
bool point_in_triangle(S& sg, const Vec3<double> (&t)[3], const Vec3<double>& x) {
  int u, v;
  const int o = projection(sg, t, u, v);
  for (int e = 0; e < 3; ++e) {
    const Vec3<double>&p = t[e], &q = t[(e + 1) % 3];
    if (o * sg.o2(p[u], p[v], q[u], q[v], x[u], x[v]) < 0) return false;
  }
  return true;
}

/// Closed segments [a, b] and [c, d] (a != b, c != d) share a point.
template <class S>
bool segments_meet(S& sg, const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c, const Vec3<double>& d) {
  if (sg.o3(a, b, c, d) != 0) return false;  // not coplanar
  const bool c_on = zero_area(sg, a, b, c), d_on = zero_area(sg, a, b, d);
  if (c_on && d_on) {  // one line: overlap along an axis on which [a, b] varies
    const int k = varying_axis(a, b);
    const double lo1 = a[k] < b[k] ? a[k] : b[k], hi1 = a[k] < b[k] ? b[k] : a[k];
    const double lo2 = c[k] < d[k] ? c[k] : d[k], hi2 = c[k] < d[k] ? d[k] : c[k];
    return !(hi1 < lo2 || hi2 < lo1);
  }
  // One plane, not one line: a projection one-to-one on it, then each segment's ends on the closed
  // opposite sides of the other's line.
  const Vec3<double> t[3] = {a, b, c_on ? d : c};
  int u, v;
  projection(sg, t, u, v);
  const int d1 = sg.o2(a[u], a[v], b[u], b[v], c[u], c[v]), d2 = sg.o2(a[u], a[v], b[u], b[v], d[u], d[v]);
  const int d3 = sg.o2(c[u], c[v], d[u], d[v], a[u], a[v]), d4 = sg.o2(c[u], c[v], d[u], d[v], b[u], b[v]);
  return d1 * d2 <= 0 && d3 * d4 <= 0;
}

/// Closed segment [a, b] (a != b) and closed triangle t (positive area) share a point.
template <class S>
bool segment_meets_triangle(S& sg, const Vec3<double>& a, const Vec3<double>& b, const Vec3<double> (&t)[3]) {
  const int sa = sg.o3(t[0], t[1], t[2], a), sb = sg.o3(t[0], t[1], t[2], b);
  if (sa * sb > 0) return false;
  if (sa == 0 && sb == 0) {  // coplanar: separating axes are t's edges and the segment's line
    int u, v;
    const int o = projection(sg, t, u, v);
    for (int e = 0; e < 3; ++e) {
      const Vec3<double>&p = t[e], &q = t[(e + 1) % 3];
      if (o * sg.o2(p[u], p[v], q[u], q[v], a[u], a[v]) < 0 && o * sg.o2(p[u], p[v], q[u], q[v], b[u], b[v]) < 0)
        return false;
    }
    int side[3];
    for (int i = 0; i < 3; ++i) side[i] = sg.o2(a[u], a[v], b[u], b[v], t[i][u], t[i][v]);
    return !one_strict_side(side);
  }
  if (sa == 0) return point_in_triangle(sg, t, a);
  if (sb == 0) return point_in_triangle(sg, t, b);
  // The segment crosses the plane inside: the line's point is in t when the three volumes with
  // t's edges are not of mixed strict signs.
  int w[3];
  for (int e = 0; e < 3; ++e) w[e] = sg.o3(a, b, t[e], t[(e + 1) % 3]);
  const bool pos = w[0] > 0 || w[1] > 0 || w[2] > 0, neg = w[0] < 0 || w[1] < 0 || w[2] < 0;
  return !(pos && neg);
}

/// The closed point sets share a point: any finite pair, zero-area triangles as segments or points.
template <class S>
std::optional<bool> meets(S& sg, const Triangle<double>& ta, const Triangle<double>& tb) {
  if (!triangle_finite(ta) || !triangle_finite(tb)) return false;
  Simplex A = reduce(sg, ta.p0, ta.p1, ta.p2), B = reduce(sg, tb.p0, tb.p1, tb.p2);
  if (sg.unknown) return std::nullopt;
  if (A.n > B.n) std::swap(A, B);
  bool r = false;
  if (A.n == 3) {
    const std::optional<TriTri> c = classify(sg, ta, tb);
    if (!c) return std::nullopt;
    return rayproof::meets(*c);
  }
  if (A.n == 1) {
    const Vec3<double>& x = A.v[0];
    if (B.n == 1) r = x == B.v[0];
    else if (B.n == 2) r = zero_area(sg, B.v[0], B.v[1], x) && between(B.v[0], B.v[1], x, varying_axis(B.v[0], B.v[1]));
    else r = sg.o3(B.v[0], B.v[1], B.v[2], x) == 0 && point_in_triangle(sg, B.v, x);
  } else if (B.n == 2) {
    r = segments_meet(sg, A.v[0], A.v[1], B.v[0], B.v[1]);
  } else {
    r = segment_meets_triangle(sg, A.v[0], A.v[1], B.v);
  }
  if (sg.unknown) return std::nullopt;
  return r;
}

}  // namespace rayproof::certified::tritri_detail
