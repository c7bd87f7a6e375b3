#pragma once
/// Conservative ray/box slab test: Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013. Each slab
/// distance is computed with at most 3 roundings (difference, reciprocal or quotient, product), so
/// scaling the exit distance by 1 + 2 gamma(3) makes the computed interval contain the exact one:
/// the test never misses a box the exact line touches. It may report a hit (or graze) for a line
/// that passes within a few ulps outside, and graze becomes hit: the class is conservative, not exact.
///
/// An axis with d_i = +-0 bounds nothing when lo_i <= o_i <= hi_i and misses otherwise, so no 0 * inf
/// NaN arises for an origin on a slab plane.
#include <algorithm>
#include <cmath>

#include "rayproof/box.h"

namespace rayproof {

template <class T>
[[nodiscard]] Hit<T> intersect_conservative(const Ray<T>& ray, const Box<T>& b) {
  if (!ray.valid() || !box_valid(b)) return {Contact::invalid};
  T t_enter, t_exit;
  if (!slab_interval(ray, b, t_enter, t_exit)) return {Contact::miss};
  // Widen the exit outward (towards +inf) by 2 gamma(3) of its magnitude, before comparing.
  const T widened = t_exit + T(2) * gamma<T>(3) * std::abs(t_exit);
  if (t_enter > widened) return {Contact::miss};
  if (widened < T(0)) return {Contact::behind, t_enter, std::max(t_enter, t_exit)};
  if (t_enter < T(0)) return {Contact::inside, t_enter, std::max(t_enter, t_exit)};
  return {t_enter == t_exit ? Contact::graze : Contact::hit, t_enter, std::max(t_enter, t_exit)};
}

}  // namespace rayproof
