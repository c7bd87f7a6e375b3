#pragma once
/// Classification of the roots of A t^2 + B t + C = 0 (A > 0) for sphere and ellipsoid, in the
/// textbook form of the worked problems: discriminant B^2 - 4AC and t = (-B -+ sqrt(disc)) / 2A.
#include <cmath>

#include "rayproof/hit.h"

namespace rayproof {

template <class T>
[[nodiscard]] Hit<T> classify_quadratic(T a, T b, T c) {
  const T disc = b * b - T(4) * a * c;
  if (!(disc >= T(0))) return {Contact::miss};  // negative (or NaN from overflow): no real root
  if (disc == T(0)) {
    const T t = -b / (T(2) * a);
    return {t < T(0) ? Contact::behind : Contact::tangent, t, t};
  }
  const T s = std::sqrt(disc);
  const T t0 = (-b - s) / (T(2) * a);
  const T t1 = (-b + s) / (T(2) * a);
  if (t1 < T(0)) return {Contact::behind, t0, t1};
  if (t0 < T(0)) return {Contact::inside, t0, t1};
  return {Contact::hit, t0, t1};
}

}  // namespace rayproof
