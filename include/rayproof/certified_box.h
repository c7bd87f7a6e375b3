#pragma once
/// Certified ray/box filter (certified_filter.h): the slab test of the exact method. The class needs
/// the entry (largest near slab distance (b_i - o_i) / d_i) against the exit (smallest far one) and
/// both against 0, and T, T2 pinned to one ulp.
///
/// Stages (certified_stage.h): (1) generic rays (every d_i != 0, every b_i - o_i exact in double,
/// checked by two-sum): each slab distance is a correctly rounded quotient and rounding is monotone,
/// so the rounded entry and exit are the rounded exact ones, and strict comparisons of rounded values
/// hold exactly: no error bound at all, and T, T2 come for free. Equal or zero rounded values (grazes
/// at corners and edges, origins on faces, slabs that round alike) are decided by exact comparisons of
/// the fractions (frac_cmp: products, then their fma error terms). Other rays (an axis with d_i = 0, a
/// b_i - o_i that rounds): every distance within 2^-51 of its magnitude, T, T2 pinned in Wide when
/// inexact; (2) exact comparisons of the fractions with expansions (degree 2); (3) the
/// running-error-bound filter, outside the exponent window. Undecided: nothing (GMP).
#include <algorithm>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// sign(p1 / d1 - p2 / d2) for doubles (d1, d2 != 0), exactly: sign(p1 d2 - p2 d1) sign(d1 d2). The
/// rounded products decide when they differ (rounding is monotone: round(X) > round(Y) implies X > Y);
/// when they are equal, the products' exact error terms (fma) decide. Nothing when an error term may
/// not be exact (a product below 2^-969 that is not an exact zero) or a product overflows.
[[nodiscard]] inline std::optional<int> frac_cmp(double p1, double d1, double p2, double d2) {
  const double x = p1 * d2, y = p2 * d1;
  int s;
  if (x != y) {
    s = x > y ? 1 : -1;
  } else {
    if (!(std::fabs(x) <= std::numeric_limits<double>::max())) return std::nullopt;
    if (x == 0) {
      if (p1 != 0 || p2 != 0) return std::nullopt;  // an underflow, not an exact zero
      s = 0;
    } else {
      if (std::fabs(x) < 0x1p-969) return std::nullopt;
      const double ex = std::fma(p1, d2, -x), ey = std::fma(p2, d1, -y);
      s = ex > ey ? 1 : (ex < ey ? -1 : 0);
    }
  }
  return (d1 < 0) != (d2 < 0) ? -s : s;
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

/// Stages 1 (general), 2 and 3 (out of line: the fast path in box() covers generic rays).
[[gnu::noinline]] inline std::optional<Hit<double>> box_rest(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  if (auto h = box_fast_general(ray, bx)) return h;
  if (auto h = box_expansion(ray, bx)) return h;
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
    Span near = span_of((Bounded(bx.lo[i]) - Bounded(ray.o[i])) / Bounded(ray.d[i]));
    Span far = span_of((Bounded(bx.hi[i]) - Bounded(ray.o[i])) / Bounded(ray.d[i]));
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

/// Stage 1 when the rounded entry and exit are equal or zero (a graze at a corner or an edge, a ray
/// starting on a face, two slab distances that round alike): every d_i != 0 and every numerator
/// p = b_i - o_i exact, as box() checked. The entry is the exact largest near fraction p / d and the
/// exit the exact smallest far one (frac_cmp), their order and signs exact; T and T2 are the
/// correctly rounded quotients of those slabs. Whatever frac_cmp cannot decide goes to box_rest.
[[gnu::noinline]] inline std::optional<Hit<double>> box_tie(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  const Vec3<double>& d = ray.d;
  double pn[3], pf[3];
  for (int i = 0; i < 3; ++i) {
    const double pa = bx.lo[i] - ray.o[i], pb = bx.hi[i] - ray.o[i];  // exact (checked by the caller)
    pn[i] = d[i] < 0 ? pb : pa, pf[i] = d[i] < 0 ? pa : pb;
  }
  int ie = 0, ix = 0;
  for (int j = 1; j < 3; ++j) {
    const auto ce = frac_cmp(pn[j], d[j], pn[ie], d[ie]), cx = frac_cmp(pf[j], d[j], pf[ix], d[ix]);
    if (!ce || !cx) return box_rest(ray, bx);
    if (*ce > 0) ie = j;
    if (*cx < 0) ix = j;
  }
  const auto order = frac_cmp(pn[ie], d[ie], pf[ix], d[ix]);
  const double t0 = pn[ie] / d[ie], t1 = pf[ix] / d[ix];
  if (!order || !(std::fabs(t0) <= std::numeric_limits<double>::max()) ||
      !(std::fabs(t1) <= std::numeric_limits<double>::max()))
    return box_rest(ray, bx);
  if (*order > 0) return H{Contact::miss};
  auto sgn = [](double p, double di) { return p == 0 ? 0 : ((p < 0) != (di < 0) ? -1 : 1); };
  if (sgn(pf[ix], d[ix]) < 0) return H{Contact::behind, t0 + 0.0, t1 + 0.0};
  if (sgn(pn[ie], d[ie]) < 0) return H{Contact::inside, t0 + 0.0, t1 + 0.0};
  return H{*order < 0 ? Contact::hit : Contact::graze, t0 + 0.0, t1 + 0.0};
}

}  // namespace detail

/// Stage 1 for every d_i != 0 and every numerator b_i - o_i exact in double (generic rays): each slab
/// distance is then a correctly rounded quotient t_i = round(x_i), and rounding is monotone, so the
/// rounded entry max_i round(x_i) is round(max_i x_i), the rounded exit likewise, and strict
/// inequalities between rounded values (and their signs) hold for the exact values. Only equal or zero
/// rounded values (box_tie) and the rest (box_rest) need more. Every result is returned as a prvalue
/// or a call (no copy of a half-written optional: that cost store-forwarding stalls).
[[nodiscard]] inline std::optional<Hit<double>> box(const Ray<double>& ray, const Box<double>& bx) {
  using H = Hit<double>;
  const Vec3<double>&o = ray.o, &d = ray.d, &lo = bx.lo, &hi = bx.hi;
#if defined(__SSE2__)
  // Two lanes at a time (x86-64 always has SSE2): the checks of ray.valid() and box_valid(), 3
  // divisions instead of 6 and the six two-sums in 3. Lanes: (x lo, y lo), (x hi, y hi), (z lo, z hi);
  // every vector built from 8-byte loads (a wider load over values just stored one by one would
  // stall store forwarding).
  const __m128d blo = _mm_set_pd(lo.y, lo.x), bhi = _mm_set_pd(hi.y, hi.x), bz = _mm_set_pd(hi.z, lo.z);
  const __m128d oxy = _mm_set_pd(o.y, o.x), oz = _mm_set1_pd(o.z), dxy = _mm_set_pd(d.y, d.x), dz = _mm_set1_pd(d.z);
  {
    // v - v is 0 in a finite lane and NaN in an infinite or NaN one; the sum keeps any NaN.
    __m128d nf = _mm_add_pd(_mm_sub_pd(blo, blo), _mm_sub_pd(bhi, bhi));
    nf = _mm_add_pd(nf, _mm_add_pd(_mm_sub_pd(bz, bz), _mm_sub_pd(oxy, oxy)));
    nf = _mm_add_pd(nf, _mm_add_pd(_mm_sub_pd(oz, oz), _mm_add_pd(_mm_sub_pd(dxy, dxy), _mm_sub_pd(dz, dz))));
    const int bad = _mm_movemask_pd(_mm_cmpunord_pd(nf, nf)) | _mm_movemask_pd(_mm_cmpgt_pd(blo, bhi)) | (lo.z > hi.z);
    if (bad || is_zero(d)) return H{Contact::invalid};
  }
#else
  // ray.valid() and box_valid() with one branch for the ten finiteness checks.
  if (!finite_bits(o.x, o.y, o.z, d.x, d.y, d.z, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z) || is_zero(d) ||
      !((lo.x <= hi.x) & (lo.y <= hi.y) & (lo.z <= hi.z)))
    return H{Contact::invalid};
#endif
  if (d.x == 0 || d.y == 0 || d.z == 0) {
    for (int i = 0; i < 3; ++i)  // parallel axis: exact comparisons of doubles
      if (d[i] == 0 && (o[i] < bx.lo[i] || o[i] > bx.hi[i])) return H{Contact::miss};
    return detail::box_rest(ray, bx);
  }
#if defined(__SSE2__)
  auto exact_sub = [](__m128d x, __m128d y, __m128d& rounded) {  // x - y, and lanes where it rounded (two-sum)
    const __m128d ny = _mm_xor_pd(y, _mm_set1_pd(-0.0)), sum = _mm_add_pd(x, ny), bb = _mm_sub_pd(sum, x);
    const __m128d err = _mm_add_pd(_mm_sub_pd(x, _mm_sub_pd(sum, bb)), _mm_sub_pd(ny, bb));
    rounded = _mm_or_pd(rounded, _mm_cmpneq_pd(err, _mm_setzero_pd()));
    return sum;
  };
  __m128d rounded = _mm_setzero_pd();
  const __m128d ta = _mm_div_pd(exact_sub(blo, oxy, rounded), dxy), tb = _mm_div_pd(exact_sub(bhi, oxy, rounded), dxy);
  const __m128d t2 = _mm_div_pd(exact_sub(bz, oz, rounded), dz);
  if (_mm_movemask_pd(rounded)) return detail::box_rest(ray, bx);
  const __m128d tn = _mm_min_pd(ta, tb), tf = _mm_max_pd(ta, tb);  // near / far of x and y
  const __m128d t2s = _mm_unpackhi_pd(t2, t2);
  const __m128d tn2 = _mm_min_sd(t2, t2s), tf2 = _mm_max_sd(t2, t2s);
  const double enter = _mm_cvtsd_f64(_mm_max_sd(_mm_max_sd(tn, _mm_unpackhi_pd(tn, tn)), tn2));
  const double exit = _mm_cvtsd_f64(_mm_min_sd(_mm_min_sd(tf, _mm_unpackhi_pd(tf, tf)), tf2));
#else
  double tn[3], tf[3];
  int inexact = 0;
  for (int i = 0; i < 3; ++i) {
    inexact += (two_sum(bx.lo[i], -o[i]).lo != 0) + (two_sum(bx.hi[i], -o[i]).lo != 0);
    const double ta = (bx.lo[i] - o[i]) / d[i], tb = (bx.hi[i] - o[i]) / d[i];
    tn[i] = ta < tb ? ta : tb, tf[i] = ta < tb ? tb : ta;
  }
  if (inexact) return detail::box_rest(ray, bx);
  auto max2 = [](double x, double y) { return x > y ? x : y; };
  auto min2 = [](double x, double y) { return x < y ? x : y; };
  const double enter = max2(max2(tn[0], tn[1]), tn[2]), exit = min2(min2(tf[0], tf[1]), tf[2]);
#endif
  if (enter > exit) return H{Contact::miss};
  if (!(enter < exit) || enter == 0 || exit == 0 || !(std::fabs(enter) <= std::numeric_limits<double>::max()) ||
      !(std::fabs(exit) <= std::numeric_limits<double>::max()))
    return detail::box_tie(ray, bx);
  return H{exit < 0 ? Contact::behind : (enter < 0 ? Contact::inside : Contact::hit), enter, exit};
}

}  // namespace rayproof::certified
