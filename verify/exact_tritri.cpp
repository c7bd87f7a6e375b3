/// rayproof::exact::tritri (rayproof/verify/exact.h), the ground truth of docs/tritri.md's classes:
/// CGAL's own triangle/triangle intersection (do_intersect and intersection on Triangle_3) on the
/// exact kernel Simple_cartesian<Gmpq>, independent of the sign-based classifier of the certified
/// tier. The class follows from what CGAL constructs:
///  - coplanar (CGAL::coplanar on a's plane and each vertex of b): a point or a segment is
///    coplanar_touching, a triangle or a polygon of positive area coplanar_overlap;
///  - otherwise a point is touching (a point interior to both would make the two chords on the
///    planes' line overlap on a segment), and a segment is crossing exactly when its midpoint lies
///    in both relative interiors (off every edge of both), else touching.
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <utility>
#include <vector>

#include "rayproof/verify/exact.h"

namespace rayproof::exact {

namespace {

using Q = CGAL::Gmpq;
using K = CGAL::Simple_cartesian<Q>;
using Point = K::Point_3;
using Segment = K::Segment_3;
using Tri = K::Triangle_3;

Point point(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }

/// m (a point of the closed triangle t) in t's relative interior: on none of its edges.
bool in_relative_interior(const Tri& t, const Point& m) {
  for (int e = 0; e < 3; ++e)
    if (Segment(t.vertex(e), t.vertex(e + 1)).has_on(m)) return false;
  return true;
}

/// Some three of the points are not collinear.
bool positive_area(const std::vector<Point>& pts) {
  for (std::size_t i = 2; i < pts.size(); ++i)
    if (!CGAL::collinear(pts[0], pts[1], pts[i])) return true;
  return false;
}

}  // namespace

TriTri tritri(const Triangle<double>& a, const Triangle<double>& b) {
  if (!triangle_finite(a) || !triangle_finite(b)) return TriTri::invalid;
  const Tri ta(point(a.p0), point(a.p1), point(a.p2)), tb(point(b.p0), point(b.p1), point(b.p2));
  if (ta.is_degenerate() || tb.is_degenerate()) return TriTri::degenerate;
  if (!CGAL::do_intersect(ta, tb)) return TriTri::disjoint;
  const bool coplanar = CGAL::coplanar(ta[0], ta[1], ta[2], tb[0]) && CGAL::coplanar(ta[0], ta[1], ta[2], tb[1]) &&
                        CGAL::coplanar(ta[0], ta[1], ta[2], tb[2]);
  const auto res = CGAL::intersection(ta, tb);
  if (!res) return TriTri::disjoint;  // do_intersect said they meet: not reached
  if (coplanar) {
    if (const Tri* t = boost::get<Tri>(&*res)) return t->is_degenerate() ? TriTri::coplanar_touching : TriTri::coplanar_overlap;
    if (const auto* poly = boost::get<std::vector<Point>>(&*res))
      return positive_area(*poly) ? TriTri::coplanar_overlap : TriTri::coplanar_touching;
    return TriTri::coplanar_touching;  // a point or a segment
  }
  if (const Segment* s = boost::get<Segment>(&*res)) {
    const Point m = CGAL::midpoint(s->source(), s->target());
    if (!s->is_degenerate() && in_relative_interior(ta, m) && in_relative_interior(tb, m)) return TriTri::crossing;
  }
  return TriTri::touching;
}

namespace {

/// A zero-area triangle's points: the segment between the two vertices farthest apart, or a point.
bool as_segment(const Tri& t, Segment& s) {
  const Point &a = t[0], &b = t[1], &c = t[2];
  const Q ab = CGAL::squared_distance(a, b), bc = CGAL::squared_distance(b, c), ca = CGAL::squared_distance(c, a);
  if (ab >= bc && ab >= ca) s = Segment(a, b);
  else if (bc >= ca) s = Segment(b, c);
  else s = Segment(c, a);
  return !s.is_degenerate();
}

}  // namespace

bool tritri_meets(const Triangle<double>& a, const Triangle<double>& b) {
  if (!triangle_finite(a) || !triangle_finite(b)) return false;
  Tri ta(point(a.p0), point(a.p1), point(a.p2)), tb(point(b.p0), point(b.p1), point(b.p2));
  if (!ta.is_degenerate() && !tb.is_degenerate()) return CGAL::do_intersect(ta, tb);
  if (!ta.is_degenerate()) std::swap(ta, tb);  // ta is zero-area from here
  Segment sa, sb;
  const bool seg_a = as_segment(ta, sa);
  if (!tb.is_degenerate()) return seg_a ? CGAL::do_intersect(sa, tb) : tb.has_on(ta[0]);
  const bool seg_b = as_segment(tb, sb);
  if (seg_a && seg_b) return CGAL::do_intersect(sa, sb);
  if (seg_a) return sa.has_on(tb[0]);
  if (seg_b) return sb.has_on(ta[0]);
  return ta[0] == tb[0];
}

}  // namespace rayproof::exact
