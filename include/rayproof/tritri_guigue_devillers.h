#pragma once
/// Guigue and Devillers' orientation-based triangle/triangle test (P. Guigue, O. Devillers, "Fast
/// and Robust Triangle-Triangle Overlap Test Using Orientation Predicates", JGT 8(1), 2003), as it
/// is usually written: every decision is the sign of a plainly computed orient3d
///   [a, b, c, d] = ((b - a) x (c - a)) . (d - a),
/// so its answers are exact wherever those signs are. True when the closed triangles meet.
///  1. The signs of a's vertices against b's plane; all equal and nonzero: no contact. The same for b.
///     All zero: the coplanar branch (tritri_coplanar.h).
///  2. Permute a circularly so that its vertex p0 is alone on its side of b's plane (p0 on the
///     positive side, or on the plane with p1 and p2 strictly negative), swapping b's last two
///     vertices when that needs the opposite orientation of b; then the same for b against a.
///  3. Then a meets L on [x02, x01] and b on [y01, y02] (the endpoints on the edges from the lone
///     vertices), and the intervals overlap exactly when [p0, p1, q0, q1] <= 0 and [p0, p2, q2, q0] <= 0.
#include <utility>

#include "rayproof/tritri_coplanar.h"

namespace rayproof {

namespace tritri_detail {

template <class T>
[[nodiscard]] T orient3(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const Vec3<T>& d) {
  return dot(cross(b - a, c - a), d - a);
}

/// Rotates (p, s) circularly so that p[0] is the lone vertex with s[0] > 0, or s[0] == 0 with
/// s[1], s[2] < 0. Returns -1 when the signs had to be negated for that (the caller swaps the
/// other triangle's last two vertices), 1 otherwise. Needs s not all of one strict sign, not all 0.
template <class T>
int make_lone_first(Vec3<T> (&p)[3], T (&s)[3]) {
  auto rotate = [&](int r) {
    const Vec3<T> q[3] = {p[r], p[(r + 1) % 3], p[(r + 2) % 3]};
    const T t[3] = {s[r], s[(r + 1) % 3], s[(r + 2) % 3]};
    for (int i = 0; i < 3; ++i) {
      p[i] = q[i];
      s[i] = t[i];
    }
  };
  for (int flip : {1, -1}) {
    for (int r = 0; r < 3; ++r) {
      const T f = static_cast<T>(flip), a = f * s[r], b = f * s[(r + 1) % 3], c = f * s[(r + 2) % 3];
      if ((a > T(0) && b <= T(0) && c <= T(0)) || (a == T(0) && b < T(0) && c < T(0))) {
        rotate(r);
        if (flip < 0)
          for (T& x : s) x = -x;
        return flip;
      }
    }
  }
  return 1;  // not reached for the sign patterns the caller passes
}

}  // namespace tritri_detail

template <class T>
[[nodiscard]] bool tritri_guigue_devillers(const Triangle<T>& ta, const Triangle<T>& tb) {
  using tritri_detail::orient3;
  Vec3<T> p[3] = {ta.p0, ta.p1, ta.p2}, q[3] = {tb.p0, tb.p1, tb.p2};
  T sp[3] = {orient3(q[0], q[1], q[2], p[0]), orient3(q[0], q[1], q[2], p[1]), orient3(q[0], q[1], q[2], p[2])};
  if ((sp[0] > T(0) && sp[1] > T(0) && sp[2] > T(0)) || (sp[0] < T(0) && sp[1] < T(0) && sp[2] < T(0))) return false;
  T sq[3] = {orient3(p[0], p[1], p[2], q[0]), orient3(p[0], p[1], p[2], q[1]), orient3(p[0], p[1], p[2], q[2])};
  if ((sq[0] > T(0) && sq[1] > T(0) && sq[2] > T(0)) || (sq[0] < T(0) && sq[1] < T(0) && sq[2] < T(0))) return false;
  if (sp[0] == T(0) && sp[1] == T(0) && sp[2] == T(0))
    return tritri_detail::coplanar_meet(cross(ta.p1 - ta.p0, ta.p2 - ta.p0), ta, tb);
  // a's lone vertex first; a negated side of b's plane is b with its last two vertices swapped
  // (b's signs against a's plane go with its vertices).
  if (tritri_detail::make_lone_first(p, sp) < 0) {
    std::swap(q[1], q[2]);
    std::swap(sq[1], sq[2]);
  }
  if (sq[0] == T(0) && sq[1] == T(0) && sq[2] == T(0))  // rounding made only b's side coplanar
    return tritri_detail::coplanar_meet(cross(ta.p1 - ta.p0, ta.p2 - ta.p0), ta, tb);
  if (tritri_detail::make_lone_first(q, sq) < 0) std::swap(p[1], p[2]);
  return orient3(p[0], p[1], q[0], q[1]) <= T(0) && orient3(p[0], p[2], q[2], q[0]) <= T(0);
}

}  // namespace rayproof
