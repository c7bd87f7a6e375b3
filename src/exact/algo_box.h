#pragma once
/// Exact ray/axis-aligned box, on a kernel K (algo_kernel.h): the slab test (Kay & Kajiya) in
/// rationals. An axis with d_i = 0 bounds nothing when lo_i <= o_i <= hi_i and misses otherwise;
/// the others bound t by (lo_i - o_i) / d_i and (hi_i - o_i) / d_i. Entry T = the largest lower
/// bound, exit T2 = the smallest upper bound, compared exactly; both rounded to nearest.
#include <cstddef>
#include <optional>
#include <utility>

#include "rayproof/box.h"
#include "rayproof/hit.h"
#include "rayproof/ray.h"
#include "exact/algo_kernel.h"

namespace rayproof::exact_algo {

template <class K>
[[nodiscard]] Hit<double> box(const Ray<double>& ray, const Box<double>& bx) {
  using Q = typename K::Q;
  constexpr Hit<double> kMiss{Contact::miss};
  std::optional<Q> enter, exit;  // d != 0, so at least one axis sets both
  for (std::size_t i = 0; i < 3; ++i) {
    const double o = ray.o[i], d = ray.d[i], lo = bx.lo[i], hi = bx.hi[i];
    if (d == 0) {  // comparisons of doubles are exact
      if (o < lo || o > hi) return kMiss;
      continue;
    }
    const Q qo(o), qd(d);
    Q t_near = (Q(lo) - qo) / qd, t_far = (Q(hi) - qo) / qd;
    if (d < 0) std::swap(t_near, t_far);
    if (!enter || *enter < t_near) enter = t_near;
    if (!exit || t_far < *exit) exit = t_far;
  }
  if (*exit < *enter) return kMiss;
  const double t_enter = rounded<K>(*enter), t_exit = rounded<K>(*exit);
  if (K::sign(*exit) < 0) return {Contact::behind, t_enter, t_exit};
  if (K::sign(*enter) < 0) return {Contact::inside, t_enter, t_exit};
  return {*enter == *exit ? Contact::graze : Contact::hit, t_enter, t_exit};
}

}  // namespace rayproof::exact_algo
