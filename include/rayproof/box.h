#pragma once
/// Ray/axis-aligned box: the slab test (Kay & Kajiya 1986), entry and exit t of the line.
/// An axis with d_i = 0 bounds nothing when lo_i <= o_i <= hi_i and misses otherwise, so no
/// 0 * inf NaN can arise.
#include <algorithm>

#include "rayproof/hit.h"
#include "rayproof/ray.h"

namespace rayproof {

template <class T>
struct Box {
  Vec3<T> lo, hi;
};

/// Which classes a slab result falls in, given entry and exit of the line (shared with robust slabs).
template <class T>
[[nodiscard]] constexpr Hit<T> classify_slab(T t_enter, T t_exit) {
  if (t_enter > t_exit) return {Contact::miss};
  if (t_exit < T(0)) return {Contact::behind, t_enter, t_exit};
  if (t_enter < T(0)) return {Contact::inside, t_enter, t_exit};
  return {t_enter == t_exit ? Contact::graze : Contact::hit, t_enter, t_exit};
}

template <class T>
[[nodiscard]] bool box_valid(const Box<T>& b) {
  return all_finite(b.lo) && all_finite(b.hi) && b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z;
}

/// The slab interval [t_enter, t_exit] of a valid ray, in plain floating point: false when an axis
/// with d_i = +-0 misses (the origin outside that slab; inside, it bounds nothing, so no 0 * inf NaN).
/// With finite d_i != 0 there is no NaN; an overflow gives a correctly signed infinity.
template <class T>
[[nodiscard]] bool slab_interval(const Ray<T>& ray, const Box<T>& b, T& t_enter, T& t_exit) {
  t_enter = -std::numeric_limits<T>::infinity();
  t_exit = std::numeric_limits<T>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (ray.d[i] == T(0)) {
      if (ray.o[i] < b.lo[i] || ray.o[i] > b.hi[i]) return false;
      continue;
    }
    T ta = (b.lo[i] - ray.o[i]) / ray.d[i];
    T tb = (b.hi[i] - ray.o[i]) / ray.d[i];
    if (ta > tb) std::swap(ta, tb);
    t_enter = std::max(t_enter, ta);
    t_exit = std::min(t_exit, tb);
  }
  return true;
}

template <class T>
[[nodiscard]] Hit<T> intersect(const Ray<T>& ray, const Box<T>& b) {
  if (!ray.valid() || !box_valid(b)) return {Contact::invalid};
  T t_enter, t_exit;
  if (!slab_interval(ray, b, t_enter, t_exit)) return {Contact::miss};
  return classify_slab(t_enter, t_exit);
}

}  // namespace rayproof
