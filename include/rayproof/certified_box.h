#pragma once
/// Certified ray/box filter (certified_filter.h): the slab test of the exact method with every slab
/// distance (b_i - o_i) / d_i as an interval. The entry is the max and the exit the min of intervals
/// (both again intervals); the class needs entry vs exit and both vs 0 decided, and T, T2 pinned to
/// one ulp. Undecided (nothing): entry and exit may be equal (a graze or a near miss) or a distance may
/// be 0 without the arithmetic making it exactly 0.
///
/// Stages (certified_stage.h): (1) slab distances in double, each within 2^-51 of its magnitude (two
/// roundings), the class from the intervals; T, T2 pinned for free when the slab's difference
/// b_i - o_i is exact in double (the quotient is then correctly rounded), else in Wide; (2) exact
/// comparisons of the fractions (b_i - o_i) / d_i with expansions (degree 2): grazes and exact ties
/// proven without GMP; (3) the running-error-bound filter below, outside the exponent window.
#include <algorithm>

#include "rayproof/box.h"
#include "rayproof/certified_filter.h"
#include "rayproof/certified_stage.h"

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


/// A slab distance (b - o) / d.
struct Slab {
  double b, o, d, t, e;  ///< bound, origin, direction, computed t, |t - exact| <= e
};

/// The slab's t within one ulp: free when b - o is exact in double, else from Wide (two roundings).
[[nodiscard]] inline std::optional<double> pin_slab(const Slab& s) {
  if (two_sum(s.b, -s.o).lo == 0) return s.t + 0.0;  // correctly rounded quotient of exact operands
  if constexpr (!kFilterAvailable) return std::nullopt;
  // b - o in Wide: one rounding (2^-64 of its magnitude); d exact.
  const Wide num = Wide(s.b) - Wide(s.o);
  return pin_ratio(num, Wide(s.d), std::fabs(num) * 0x1p-64L, 0);
}

/// The class from the entry interval [El, Eh] and the exit interval [Xl, Xh] (entry before exit,
/// decided by the caller): behind, inside or hit, or nothing when 0 falls in either interval.
[[nodiscard]] inline std::optional<Contact> slab_class(double El, double Eh, double Xl, double Xh) {
  if (Xh < 0) return Contact::behind;
  if (!(Xl >= 0)) return std::nullopt;
  if (Eh < 0) return Contact::inside;
  if (El >= 0) return Contact::hit;
  return std::nullopt;
}

/// Stage 1 in general (some d_i = 0, or a b - o that is not exact in double): near[i] / far[i] for
/// the axes with d_i != 0, each t pinned by pin_slab.
[[gnu::noinline]] inline std::optional<Hit<double>> box_fast_general(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  Slab near[3], far[3];
  int k = 0;
  for (int i = 0; i < 3; ++i) {
    if (ray.d[i] == 0) continue;  // the caller checked o_i within the slab
    const bool neg = ray.d[i] < 0;
    const double lo = neg ? bx.hi[i] : bx.lo[i], hi = neg ? bx.lo[i] : bx.hi[i];
    const double tn = (lo - ray.o[i]) / ray.d[i], tf = (hi - ray.o[i]) / ray.d[i];
    if (!(std::fabs(tn) < 0x1p1020 && std::fabs(tf) < 0x1p1020)) return std::nullopt;  // overflow
    // Two roundings (2^-51 with slack), and 2^-1000 (normal, so no slow subnormal arithmetic) for a quotient that underflows.
    near[k] = {lo, ray.o[i], ray.d[i], tn, std::fabs(tn) * 0x1p-51 + 0x1p-1000};
    far[k] = {hi, ray.o[i], ray.d[i], tf, std::fabs(tf) * 0x1p-51 + 0x1p-1000};
    ++k;
  }
  // Entry: the largest near interval, unambiguous (every other one lies below it); exit likewise.
  int ie = 0, ix = 0;
  for (int j = 1; j < k; ++j) {
    if (near[j].t > near[ie].t) ie = j;
    if (far[j].t < far[ix].t) ix = j;
  }
  const Slab &en = near[ie], &ex = far[ix];
  const double El = en.t - en.e, Eh = en.t + en.e, Xl = ex.t - ex.e, Xh = ex.t + ex.e;
  if (El > Xh) return H{Contact::miss};
  for (int j = 0; j < k; ++j) {
    if (j != ie && !(near[j].t + near[j].e < El)) return std::nullopt;
    if (j != ix && !(far[j].t - far[j].e > Xh)) return std::nullopt;
  }
  if (!(Eh < Xl)) return std::nullopt;  // a graze, or too close to tell
  const auto cls = slab_class(El, Eh, Xl, Xh);
  if (!cls) return std::nullopt;
  const auto t0 = pin_slab(en), t1 = pin_slab(ex);
  if (!t0 || !t1) return std::nullopt;
  return H{*cls, *t0, *t1};
}

/// Stage 1, every d_i != 0 and every b - o exact in double (then each slab distance is a correctly
/// rounded quotient and needs no pinning): the decisions of box_fast_general without data-dependent
/// branches (random rays mispredicted about two a test there): near / far by min / max, entry and
/// exit by max / min, and "unambiguous" as a count: exactly one near interval reaches El (the entry's
/// own) and exactly one far interval reaches Xh. Anything else goes to box_fast_general.
[[nodiscard]] inline std::optional<Hit<double>> box_fast(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  if (ray.d.x == 0 || ray.d.y == 0 || ray.d.z == 0) return box_fast_general(ray, bx);
  double tn[3], tf[3];
  int inexact = 0;
  for (int i = 0; i < 3; ++i) {
    inexact += (two_sum(bx.lo[i], -ray.o[i]).lo != 0) + (two_sum(bx.hi[i], -ray.o[i]).lo != 0);
    const double ta = (bx.lo[i] - ray.o[i]) / ray.d[i], tb = (bx.hi[i] - ray.o[i]) / ray.d[i];
    tn[i] = ta < tb ? ta : tb, tf[i] = ta < tb ? tb : ta;
  }
  if (inexact) return box_fast_general(ray, bx);
  auto max2 = [](double x, double y) { return x > y ? x : y; };
  auto min2 = [](double x, double y) { return x < y ? x : y; };
  const double enter = max2(max2(tn[0], tn[1]), tn[2]), exit = min2(min2(tf[0], tf[1]), tf[2]);
  const double big = std::fabs(tn[0]) + std::fabs(tn[1]) + std::fabs(tn[2]) + std::fabs(tf[0]) + std::fabs(tf[1]) +
                     std::fabs(tf[2]);
  if (!(big < 0x1p1020)) return std::nullopt;  // overflow
  // One rounding each (exact numerators): 2^-51 is ample; 2^-1000 for a quotient that underflows.
  auto err = [](double t) { return std::fabs(t) * 0x1p-51 + 0x1p-1000; };
  const double El = enter - err(enter), Eh = enter + err(enter), Xl = exit - err(exit), Xh = exit + err(exit);
  if (El > Xh) return H{Contact::miss};
  int reach = 0;
  for (int j = 0; j < 3; ++j) reach += (tn[j] + err(tn[j]) >= El) + (tf[j] - err(tf[j]) <= Xh);
  if (reach != 2 || !(Eh < Xl)) return std::nullopt;  // a tie between slabs, a graze, or too close
  const auto cls = slab_class(El, Eh, Xl, Xh);
  if (!cls) return std::nullopt;
  return H{*cls, enter + 0.0, exit + 0.0};  // a zero is +0.0
}

/// Stage 2 (in_range<-300, 300>, degree 2): slab distances as exact fractions p / d, compared exactly.
[[gnu::noinline, gnu::cold]] inline std::optional<Hit<double>> box_expansion(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &d = ray.d, &lo = bx.lo, &hi = bx.hi;
  if (!in_range<-300, 300>(o.x, o.y, o.z, d.x, d.y, d.z, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z)) return std::nullopt;
  struct Frac {
    Expansion p;
    double d;
  };
  // sign(p1 / d1 - p2 / d2) = sign(p1 d2 - p2 d1) sign(d1 d2).
  auto cmp = [](const Frac& x, const Frac& y) {
    const Expansion z = x.p * Expansion(y.d) - y.p * Expansion(x.d);
    return std::optional<int>(z.bad ? std::nullopt : std::optional<int>(z.sign() * ((x.d < 0) != (y.d < 0) ? -1 : 1)));
  };
  std::optional<Frac> enter, exit;
  for (int i = 0; i < 3; ++i) {
    if (ray.d[i] == 0) continue;
    const bool neg = ray.d[i] < 0;
    Frac n{diff(neg ? bx.hi[i] : bx.lo[i], ray.o[i]), ray.d[i]}, f{diff(neg ? bx.lo[i] : bx.hi[i], ray.o[i]), ray.d[i]};
    if (!enter) {
      enter = n, exit = f;
      continue;
    }
    const auto ce = cmp(n, *enter), cx = cmp(f, *exit);
    if (!ce || !cx) return std::nullopt;
    if (*ce > 0) enter = n;
    if (*cx < 0) exit = f;
  }
  const auto order = cmp(*enter, *exit);
  if (!order) return std::nullopt;
  if (*order > 0) return H{Contact::miss};
  const auto t0 = pin_quotient(enter->p, Expansion(enter->d)), t1 = pin_quotient(exit->p, Expansion(exit->d));
  if (!t0 || !t1) return std::nullopt;
  const int s_enter = enter->p.sign() * (enter->d < 0 ? -1 : 1), s_exit = exit->p.sign() * (exit->d < 0 ? -1 : 1);
  if (s_exit < 0) return H{Contact::behind, *t0, *t1};
  if (s_enter < 0) return H{Contact::inside, *t0, *t1};
  return H{*order < 0 ? Contact::hit : Contact::graze, *t0, *t1};
}

}  // namespace detail

[[nodiscard]] inline std::optional<Hit<double>> box(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  using detail::Span;
  if (!ray.valid() || !box_valid(bx)) return H{Contact::invalid};
  for (int i = 0; i < 3; ++i)  // parallel axis: exact comparisons of doubles
    if (ray.d[i] == 0 && (ray.o[i] < bx.lo[i] || ray.o[i] > bx.hi[i])) return H{Contact::miss};
  if (auto h = detail::box_fast(ray, bx)) return h;
  if (auto h = detail::box_expansion(ray, bx)) return h;
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
