#pragma once
/// Exact signs from two_sum / two_prod terms, summed in a certified::Expansion, for
/// ExactMesh::ray_crossings (crossings.cpp): the edge function of a ray and an edge when
/// the differences from the origin are exact in double.
#include "rayproof/certified_expansion.h"
#include "rayproof/float_util.h"
#include "rayproof/vec3.h"

namespace rayproof::scene::detail {

/// The exact sign of u = d . (B x C) when B = a - o and C = b - o are exact in double (often so when
/// a ray is aimed along an axis at a vertex): every product two_prod'ed into at most 24 terms.
/// Returns 2 when a difference is not exact.
inline int u_sign_exact_small(const Vec3<double>& d, const Vec3<double>& o, const Vec3<double>& a, const Vec3<double>& b) {
  const double A[3] = {a.x, a.y, a.z}, O[3] = {o.x, o.y, o.z}, Bv[3] = {b.x, b.y, b.z}, D[3] = {d.x, d.y, d.z};
  double B[3], C[3];
  for (int c = 0; c < 3; ++c) {
    const TwoTerm<double> x = two_sum(A[c], -O[c]), y = two_sum(Bv[c], -O[c]);
    if (x.lo != 0 || y.lo != 0) return 2;
    B[c] = x.hi, C[c] = y.hi;
  }
  certified::Expansion sum;  // at most 24 components: far below its capacity, never `bad`
  for (int c = 0; c < 3; ++c) {
    if (D[c] == 0) continue;
    const int j = (c + 1) % 3, k = (c + 2) % 3;
    const TwoTerm<double> p = two_prod(B[j], C[k]), q = two_prod(B[k], C[j]);
    for (const double v : {p.hi, p.lo, -q.hi, -q.lo}) {
      if (v == 0) continue;
      const TwoTerm<double> w = two_prod(D[c], v);
      sum.grow(w.hi);
      if (w.lo != 0) sum.grow(w.lo);
    }
  }
  return sum.sign();
}

}  // namespace rayproof::scene::detail
