#pragma once
/// GoogleTest helpers: check a kernel's answer for one ray and one primitive against the exact answer
/// (rayproof/verify/exact.h, the ground truth on CGAL). Header-only; the test links GTest and
/// rayproof::verify (CGAL, GMP, MPFR), which provides rayproof::exact::intersect.
///
///   auto kernel = [](const auto& ray, const auto& prim) { return my::intersect(ray, prim); };
///   EXPECT_RAY_HIT_MATCHES_EXACT(kernel, ray, triangle, 2);   // or ASSERT_...
///   EXPECT_TRUE(rayproof::gtest::matches_exact(kernel, ray, triangle, 2));
///
/// kernel: any callable taking (const Ray<T>&, const Prim<T>&) for T = float or double and returning
/// Hit<T> (TriangleHit<T> for triangles) or anything with .contact, .t, .t2 of those meanings.
/// It matches when its class is the exact class and every t the class carries (docs/cases.md: t for
/// hits and behind; t2 too for spheres, ellipsoids and boxes; [t, t2] for a coplanar triangle
/// range) is within max_ulps ulps, in T, of the exact value rounded to T. The exact answer is that
/// of exact arithmetic on the inputs as given (a float input is a double exactly); for T = float the
/// exact t is rounded to double, then to float, which near a tie can be one float ulp from the
/// correctly rounded float. A failure prints the case as a docs/cases.md line (a one-line reproducer for
/// `rayproof classify` or `rayproof verify`), the exact answer, the kernel's answer and the ulp
/// distances, as `CLASS T T2` lines.
///
/// Triangle pairs: EXPECT_TRITRI_MATCHES_EXACT(kernel, a, b) with kernel(a, b) returning bool (meets)
/// or rayproof::TriTri (docs/tritri.md); the failure prints the pair's `tritri` case line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <type_traits>

#include "rayproof/verify/exact.h"
#include "rayproof/float_util.h"

namespace rayproof::gtest {

namespace detail {

/// Shortest %.Ng text that reads back (strtod) to the same double; "nan", "inf", "-0" as printed.
inline std::string number(double x) {
  char buf[40];
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, x);
    if (std::isnan(x) || std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

inline void append(std::string& s, double x) { s += ' ' + number(x); }
inline void append(std::string& s, const Vec3<double>& v) { append(s, v.x), append(s, v.y), append(s, v.z); }

template <class T> Vec3<double> wide(const Vec3<T>& v) { return v.template cast<double>(); }

// The primitive in double (exact for float inputs), its docs/cases.md kind and fields.
template <class T> Plane<double> wide(const Plane<T>& p) { return {wide(p.point), wide(p.normal)}; }
template <class T> Sphere<double> wide(const Sphere<T>& s) { return {wide(s.center), double(s.radius)}; }
template <class T> Ellipsoid<double> wide(const Ellipsoid<T>& e) { return {wide(e.center), wide(e.semi_axes)}; }
template <class T> Box<double> wide(const Box<T>& b) { return {wide(b.lo), wide(b.hi)}; }
template <class T> Disk<double> wide(const Disk<T>& d) { return {wide(d.center), wide(d.normal), double(d.radius)}; }
template <class T> Triangle<double> wide(const Triangle<T>& t) { return {wide(t.p0), wide(t.p1), wide(t.p2)}; }

inline const char* kind_name(const Plane<double>&) { return "plane"; }
inline const char* kind_name(const Sphere<double>&) { return "sphere"; }
inline const char* kind_name(const Ellipsoid<double>&) { return "ellipsoid"; }
inline const char* kind_name(const Box<double>&) { return "box"; }
inline const char* kind_name(const Disk<double>&) { return "disk"; }
inline const char* kind_name(const Triangle<double>&) { return "triangle"; }

inline void append_prim(std::string& s, const Plane<double>& p) { append(s, p.point), append(s, p.normal); }
inline void append_prim(std::string& s, const Sphere<double>& p) { append(s, p.center), append(s, p.radius); }
inline void append_prim(std::string& s, const Ellipsoid<double>& p) { append(s, p.center), append(s, p.semi_axes); }
inline void append_prim(std::string& s, const Box<double>& p) { append(s, p.lo), append(s, p.hi); }
inline void append_prim(std::string& s, const Disk<double>& p) {
  append(s, p.center), append(s, p.normal), append(s, p.radius);
}
inline void append_prim(std::string& s, const Triangle<double>& p) { append(s, p.p0), append(s, p.p1), append(s, p.p2); }

/// The docs/cases.md case line of a ray and a primitive (in double).
template <class Prim>
std::string case_line(const Ray<double>& ray, const Prim& prim) {
  std::string s = kind_name(prim);
  append(s, ray.o), append(s, ray.d), append_prim(s, prim);
  return s;
}

/// Which of t, t2 a class carries for a kind (docs/cases.md; the same rule as the CLI's output).
struct Carried {
  bool t = false, t2 = false;
};
inline Carried carried(bool two_values, bool is_triangle, Contact c) {
  switch (c) {
    case Contact::coplanar: return {is_triangle, is_triangle};  // the range, or "- -"
    case Contact::behind: case Contact::hit: case Contact::interior: case Contact::edge: case Contact::vertex:
    case Contact::rim: case Contact::tangent: case Contact::inside: case Contact::graze:
      return {true, two_values};
    default:
      return {};
  }
}

/// `CLASS T T2` with `-` for what the class does not carry (a coplanar triangle without range: NaN).
inline std::string result_line(Contact c, double t, double t2, Carried k) {
  std::string s(to_string(c));
  s += ' ' + (k.t && !(c == Contact::coplanar && std::isnan(t)) ? number(t) : std::string("-"));
  s += ' ' + (k.t2 && !(c == Contact::coplanar && std::isnan(t2)) ? number(t2) : std::string("-"));
  return s;
}

/// ulp distance in T, the coplanar "no range" (NaN) matching only itself.
template <class T>
std::uint64_t distance(T got, T want) {
  if (std::isnan(got) && std::isnan(want)) return 0;
  return ulp_distance(got, want);
}

}  // namespace detail

/// The check behind EXPECT_RAY_HIT_MATCHES_EXACT: success, or a failure whose message holds the
/// case line, the exact and kernel answers and the ulp distances.
template <class Kernel, class T, template <class> class Prim>
::testing::AssertionResult matches_exact(Kernel&& kernel, const Ray<T>& ray, const Prim<T>& prim, std::uint64_t max_ulps) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>, "rays and primitives in float or double");
  const Ray<double> ray_d{detail::wide(ray.o), detail::wide(ray.d)};
  const auto prim_d = detail::wide(prim);
  const auto want = exact::intersect(ray_d, prim_d);
  const auto got = kernel(ray, prim);
  using P = std::decay_t<decltype(prim_d)>;
  const bool two = std::is_same_v<P, Sphere<double>> || std::is_same_v<P, Ellipsoid<double>> || std::is_same_v<P, Box<double>>;
  const bool tri = std::is_same_v<P, Triangle<double>>;
  const detail::Carried k = detail::carried(two, tri, want.contact);
  const T want_t = static_cast<T>(want.t), want_t2 = static_cast<T>(want.t2);
  const T got_t = static_cast<T>(got.t), got_t2 = static_cast<T>(got.t2);
  const std::uint64_t d1 = k.t ? detail::distance(got_t, want_t) : 0, d2 = k.t2 ? detail::distance(got_t2, want_t2) : 0;
  const bool same_class = got.contact == want.contact;
  if (same_class && d1 <= max_ulps && d2 <= max_ulps) return ::testing::AssertionSuccess();

  auto ulps = [](std::uint64_t d) {
    if (d == std::numeric_limits<std::uint64_t>::max()) return std::string("NaN or inf vs finite");
    return std::to_string(d) + (d == 1 ? " ulp" : " ulps");
  };
  std::string why;
  if (!same_class) why = "class " + std::string(to_string(got.contact)) + " != exact " + std::string(to_string(want.contact));
  else {
    if (d1 > max_ulps) why = "t off by " + ulps(d1);
    if (d2 > max_ulps) why += (why.empty() ? "" : ", ") + std::string("t2 off by ") + ulps(d2);
    why += " (max " + std::to_string(max_ulps) + ")";
  }
  const detail::Carried kg = detail::carried(two, tri, got.contact);
  std::string ulp_note;
  if (same_class) {
    ulp_note = "  (";
    if (k.t) ulp_note += "t: " + ulps(d1);
    if (k.t2) ulp_note += ", t2: " + ulps(d2);
    ulp_note += std::is_same_v<T, float> ? " of float)" : " of double)";
    if (!k.t && !k.t2) ulp_note.clear();
  }
  return ::testing::AssertionFailure()
         << "kernel answer does not match exact: " << why << "\n"
         << "  case:   " << detail::case_line(ray_d, prim_d) << "\n"
         << "  exact:  " << detail::result_line(want.contact, want.t, want.t2, k) << "\n"
         << "  kernel: " << detail::result_line(got.contact, double(got_t), double(got_t2), kg) << ulp_note << "\n";
}

/// The check behind EXPECT_TRITRI_MATCHES_EXACT: a triangle/triangle kernel (docs/tritri.md) against
/// exact arithmetic. kernel(a, b) takes two Triangle<T> (T = float or double) and returns either a
/// bool, whether the closed triangles meet, compared with exact::tritri_meets (zero-area triangles
/// included), or a rayproof::TriTri class, compared with exact::tritri. A failure prints the pair as a
/// docs/cases.md `tritri` line (a one-line reproducer for `rayproof classify` or `rayproof verify`),
/// the exact answer and the kernel's.
template <class Kernel, class T>
::testing::AssertionResult tritri_matches_exact(Kernel&& kernel, const Triangle<T>& a, const Triangle<T>& b) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>, "triangles in float or double");
  const Triangle<double> ad = detail::wide(a), bd = detail::wide(b);
  const auto got = kernel(a, b);
  using Answer = std::decay_t<decltype(got)>;
  static_assert(std::is_same_v<Answer, bool> || std::is_same_v<Answer, TriTri>,
                "a triangle/triangle kernel returns bool (they meet) or rayproof::TriTri");
  std::string line = "tritri";
  detail::append_prim(line, ad), detail::append_prim(line, bd);
  std::string want_text, got_text;
  bool same = false;
  if constexpr (std::is_same_v<Answer, bool>) {
    const bool want = exact::tritri_meets(ad, bd);
    same = got == want;
    want_text = want ? "meets (" + std::string(to_string(exact::tritri(ad, bd))) + ")" : "disjoint";
    got_text = got ? "meets" : "disjoint";
  } else {
    const TriTri want = exact::tritri(ad, bd);
    same = got == want;
    want_text = std::string(to_string(want));
    got_text = std::string(to_string(got));
  }
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "kernel answer does not match exact\n"
                                       << "  case:   " << line << "\n"
                                       << "  exact:  " << want_text << "\n"
                                       << "  kernel: " << got_text << "\n";
}

}  // namespace rayproof::gtest

/// Non-fatal / fatal check that kernel(a, b), a triangle/triangle test returning bool (meets) or a
/// TriTri class, agrees with exact arithmetic (see tritri_matches_exact above).
#define EXPECT_TRITRI_MATCHES_EXACT(kernel, a, b) EXPECT_TRUE(::rayproof::gtest::tritri_matches_exact(kernel, a, b))
#define ASSERT_TRITRI_MATCHES_EXACT(kernel, a, b) ASSERT_TRUE(::rayproof::gtest::tritri_matches_exact(kernel, a, b))

/// Non-fatal / fatal check that kernel(ray, prim) has the exact class and its t values within
/// max_ulps ulps of the exact ones (see the top of rayproof/verify/gtest.h).
#define EXPECT_RAY_HIT_MATCHES_EXACT(kernel, ray, prim, max_ulps) \
  EXPECT_TRUE(::rayproof::gtest::matches_exact(kernel, ray, prim, max_ulps))
#define ASSERT_RAY_HIT_MATCHES_EXACT(kernel, ray, prim, max_ulps) \
  ASSERT_TRUE(::rayproof::gtest::matches_exact(kernel, ray, prim, max_ulps))
