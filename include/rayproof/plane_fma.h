#pragma once
/// Ray/plane with FMA-compensated dot products: t = ((p - o) . n) / (d . n), each dot product as
/// accurate as if computed in twice the precision (Dot2: Ogita, Rump & Oishi 2005; the same error-
/// free products as pbrt-v4's DifferenceOfProducts / InnerProduct). The sign of d . n, which decides
/// parallel, is then exact unless it cancels below about u^2 of its terms; p - o still rounds once.
#include "rayproof/plane.h"

namespace rayproof {

/// a . b with compensated products and sums.
template <class T>
[[nodiscard]] inline T dot_fma(const Vec3<T>& a, const Vec3<T>& b) {
  return compensated_dot3(a.x, b.x, a.y, b.y, a.z, b.z);
}

template <class T>
[[nodiscard]] Hit<T> intersect_fma(const Ray<T>& ray, const Plane<T>& pl) {
  if (!ray.valid() || !all_finite(pl.point) || !all_finite(pl.normal)) return {Contact::invalid};
  if (is_zero(pl.normal)) return {Contact::degenerate};
  // Denominator and numerator, each rounded about once.
  const T denom = dot_fma(ray.d, pl.normal);
  const T num = dot_fma(pl.point - ray.o, pl.normal);
  if (denom == T(0)) return {num == T(0) ? Contact::coplanar : Contact::parallel};
  const T t = num / denom;
  return {t < T(0) ? Contact::behind : Contact::hit, t};
}

}  // namespace rayproof
