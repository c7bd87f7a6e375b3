#pragma once
/// Certified ray/box filter (certified_filter.h): the slab test of the exact method with every slab
/// distance (b_i - o_i) / d_i as an interval. The entry is the max and the exit the min of intervals
/// (both again intervals); the class needs entry vs exit and both vs 0 decided, and T, T2 pinned to
/// one ulp. Undecided (nothing): entry and exit may be equal (a graze or a near miss) or a distance may
/// be 0 without the arithmetic making it exactly 0.
#include <algorithm>

#include "rayproof/box.h"
#include "rayproof/certified_filter.h"

namespace rayproof::certified {

namespace detail {

/// A closed interval [lo, hi] with a best estimate mid.
struct Span {
  Wide lo, hi, mid;
};

/// The interval of a bounded quantity, outward by its radius (with slack) and 2 u |v| for rounding.
inline Span span_of(Bounded a) {
  const Wide w = a.r == 0 ? Wide(0) : a.r * kSlack + 2 * Bounded::kU * std::fabs(a.v);
  return {a.v - w, a.v + w, a.v};
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> box(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  using detail::Span;
  if (!ray.valid() || !box_valid(bx)) return H{Contact::invalid};
  if constexpr (!kFilterAvailable) return std::nullopt;
  constexpr Wide inf = std::numeric_limits<Wide>::infinity();
  Span enter{-inf, -inf, -inf}, exit{inf, inf, inf};
  for (int i = 0; i < 3; ++i) {
    // Parallel axis: exact comparisons of doubles.
    if (ray.d[i] == 0) {
      if (ray.o[i] < bx.lo[i] || ray.o[i] > bx.hi[i]) return H{Contact::miss};
      continue;
    }
    // Slab distances; near is the one with the smaller value (d_i < 0 swaps them).
    Span near = detail::span_of((Bounded(bx.lo[i]) - Bounded(ray.o[i])) / Bounded(ray.d[i]));
    Span far = detail::span_of((Bounded(bx.hi[i]) - Bounded(ray.o[i])) / Bounded(ray.d[i]));
    if (ray.d[i] < 0) std::swap(near, far);
    // max / min of intervals: componentwise.
    enter = {std::max(enter.lo, near.lo), std::max(enter.hi, near.hi), std::max(enter.mid, near.mid)};
    exit = {std::min(exit.lo, far.lo), std::min(exit.hi, far.hi), std::min(exit.mid, far.mid)};
  }
  // entry > exit: miss; possibly equal: undecided.
  if (enter.lo > exit.hi) return H{Contact::miss};
  if (!(enter.hi < exit.lo)) {
    // Both exactly the same point (degenerate intervals): a graze at that t.
    if (!(enter.lo == enter.hi && exit.lo == exit.hi && enter.lo == exit.lo)) return std::nullopt;
  }
  const auto t0 = pin_interval(enter.lo, enter.hi, enter.mid), t1 = pin_interval(exit.lo, exit.hi, exit.mid);
  if (!t0 || !t1) return std::nullopt;
  if (exit.hi < 0) return H{Contact::behind, *t0, *t1};
  if (!(exit.lo >= 0)) return std::nullopt;
  if (enter.hi < 0) return H{Contact::inside, *t0, *t1};
  if (!(enter.lo >= 0)) return std::nullopt;
  return H{enter.hi < exit.lo ? Contact::hit : Contact::graze, *t0, *t1};
}

}  // namespace rayproof::certified
