/// Exact ray/axis-aligned box: the slab test (Kay & Kajiya) in rationals. An axis with d_i = 0
/// bounds nothing when lo_i <= o_i <= hi_i and misses otherwise; the others bound t by
/// (lo_i - o_i) / d_i and (hi_i - o_i) / d_i. Entry T = the largest lower bound, exit T2 = the
/// smallest upper bound, compared exactly; both rounded to nearest.
#include <optional>
#include <utility>

#include "verify/fallback_kinds.h"
#include "verify/fallback_number.h"
#include "verify/fallback_rounding.h"

namespace rayproof::certified::fallback {

Hit<double> box_kernel(const Ray<double>& ray, const Box<double>& box) {
  constexpr Hit<double> kMiss{Contact::miss};
  std::optional<Q> enter, exit;  // d != 0, so at least one axis sets both
  for (std::size_t i = 0; i < 3; ++i) {
    const double o = ray.o[i], d = ray.d[i], lo = box.lo[i], hi = box.hi[i];
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
  const double t_enter = round_nearest(*enter), t_exit = round_nearest(*exit);
  if (sign(*exit) < 0) return {Contact::behind, t_enter, t_exit};
  if (sign(*enter) < 0) return {Contact::inside, t_enter, t_exit};
  return {*enter == *exit ? Contact::graze : Contact::hit, t_enter, t_exit};
}

}  // namespace rayproof::certified::fallback
