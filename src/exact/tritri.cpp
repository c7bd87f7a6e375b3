// rayproof::certified::tritri (rayproof/certified/tritri.h): the sign-based classifier of
// rayproof/certified_tritri.h on the signs of orient_exact.h (filter, expansions, then GMP), which
// are never unknown, so the class is always decided and exact.
#include "rayproof/certified/tritri.h"

#include "exact/orient_exact.h"

namespace rayproof::certified {

namespace {

auto exact_signs() {
  auto o3 = [](const Vec3<double>& p, const Vec3<double>& q, const Vec3<double>& r, const Vec3<double>& s) {
    return orient3d_exact(p, q, r, s);
  };
  auto o2 = [](double au, double av, double bu, double bv, double pu, double pv) {
    return orient2d_exact(au, av, bu, bv, pu, pv);
  };
  return tritri_detail::Signs<decltype(o3), decltype(o2)>{o3, o2};
}

}  // namespace

bool tritri_meets(const Triangle<double>& a, const Triangle<double>& b) {
  auto signs = exact_signs();
  return tritri_detail::meets(signs, a, b).value_or(false);  // always decided
}

TriTri tritri(const Triangle<double>& a, const Triangle<double>& b) {
  auto o3 = [](const Vec3<double>& p, const Vec3<double>& q, const Vec3<double>& r, const Vec3<double>& s) {
    return orient3d_exact(p, q, r, s);
  };
  auto o2 = [](double au, double av, double bu, double bv, double pu, double pv) {
    return orient2d_exact(au, av, bu, bv, pu, pv);
  };
  tritri_detail::Signs<decltype(o3), decltype(o2)> signs{o3, o2};
  // Every sign is decided (orient*_exact never returns kUnknown), so classify always answers.
  return tritri_detail::classify(signs, a, b).value_or(TriTri::invalid);
}

}  // namespace rayproof::certified
