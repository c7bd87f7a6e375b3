#pragma once
/// The named result every kernel returns: the contact class and the t values the class carries.
#include "rayproof/contact.h"
#include "rayproof/float_util.h"

namespace rayproof {

/// Result of a ray against a plane, quadric, box or disk.
/// plane, disk: t = the plane parameter (t2 unused). sphere, ellipsoid: t <= t2 are the two roots.
/// box: t = entry, t2 = exit. Unused fields are NaN.
template <class T>
struct Hit {
  Contact contact = Contact::miss;
  T t = kNaN<T>;
  T t2 = kNaN<T>;
};

/// Result of a ray against a triangle p0 p1 p2: t, and barycentrics b1 (weight of p1), b2 (of p2),
/// b0 = 1 - b1 - b2. coplanar: [t, t2] is the range of t >= 0 on the closed triangle.
template <class T>
struct TriangleHit {
  Contact contact = Contact::miss;
  T t = kNaN<T>;
  T t2 = kNaN<T>;
  T b1 = kNaN<T>;
  T b2 = kNaN<T>;
};

}  // namespace rayproof
